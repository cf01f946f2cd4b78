"""Checks that a typed result holds its JSON document's values: arrays are float64 of the
document's length and equal to its numbers (null as NaN), strings and units are the
document's, parameters' names, values and intervals are the document's."""
import json
import math

import numpy as np

FIGURES = (("N", "white"), ("K", "walk"), ("B", "instability"), ("Q", "quantization"), ("R", "ramp"))


def same(typed, value):
    """A typed scalar equals the JSON value (null: NaN for a float, else None)."""
    if value is None:
        return typed is None or (isinstance(typed, float) and math.isnan(typed))
    return typed == value


def assert_same(typed, value, what=""):
    assert same(typed, value), f"{what}: {typed!r} != {value!r}"


def assert_floats(array, values, what=""):
    assert isinstance(array, np.ndarray), what
    assert array.dtype == np.float64, what
    assert array.shape == (len(values),), what
    expected = np.array([np.nan if v is None else v for v in values], dtype=np.float64)
    np.testing.assert_array_equal(array, expected, err_msg=what)


def assert_fields(obj, d, keys):
    for key in keys:
        assert_same(getattr(obj, key), d[key], key)


def assert_text_is_the_document(result, document):
    """to_json() parses back to the document, with every float equal."""
    assert json.loads(result.to_json()) == document
    assert result.document == document


def check_wv_levels(levels, rows):
    assert len(levels) == len(rows)
    for key in ("tau", "tau_seconds", "wv", "ci_low", "ci_high"):
        assert_floats(getattr(levels, key), [r[key] for r in rows], key)
    assert levels.level.tolist() == [r["level"] for r in rows]
    assert levels.coefficients.tolist() == [r["coefficients"] for r in rows]
    assert list(levels.note) == [r.get("note") for r in rows]
    robust = "classical_wv" in rows[0]
    for key in ("classical_wv", "robust_to_classical", "rounding_ratio", "tail_share"):
        if robust:
            assert_floats(getattr(levels, key), [r[key] for r in rows], key)
        else:
            assert getattr(levels, key) is None
    for key in ("ci_disjoint", "contaminated"):
        if robust:
            assert getattr(levels, key).tolist() == [r[key] for r in rows]


def check_parameters(params, rows):
    assert len(params) == len(rows)
    for p, r in zip(params, rows):
        assert_fields(p, r, ("process", "component", "name", "value", "se", "ci_low", "ci_high", "interval"))
        assert isinstance(p.value, float)


def check_continuous(rows_typed, rows):
    assert len(rows_typed) == len(rows)
    for p, r in zip(rows_typed, rows):
        assert_fields(p, r, ("process", "name", "value", "ci_low", "ci_high", "unit", "convention"))
        assert_same(p.component, r.get("component"), "component")


def check_gof(gof, d):
    assert_fields(gof, d, ("statistic", "df", "p_value", "method"))


def check_kalman(kalman, d):
    assert_same(kalman.filter_rate, d["filter_rate"])
    assert len(kalman.terms) == len(d["terms"])
    for t, r in zip(kalman.terms, d["terms"]):
        assert_fields(t, r, ("process", "component", "role", "q", "q_unit", "transition", "discrete", "discrete_unit",
                             "note"))


def check_allan(allan, d):
    if d is None:
        assert allan is None
        return
    for key in ("tau", "adev", "ci_low", "ci_high", "edf"):
        assert_floats(getattr(allan, key), d[key], key)
    assert allan.m.tolist() == d["m"]
    assert_same(allan.alpha, d["alpha"])
    if d["model"] is None:
        assert allan.model is None
    else:
        assert_floats(allan.model, d["model"], "model")


def check_readoff(r, d):
    assert_fields(r, d, ("value", "low", "high", "status", "tau", "region_from", "region_to", "how"))
    assert [(c.component, c.share) for c in r.components] == [(c["component"], c["share"]) for c in d["components"]]


def check_noise_figures(figures, d):
    if d is None:
        assert figures is None
        return
    for attr, key in FIGURES:
        f, j = getattr(figures, attr), d[key]
        check_readoff(f, j)
        assert_fields(f, j, ("unit", "source", "note"))
        assert f.interval == (f.low, f.high)
        check_readoff(f.model, j["model"])
        check_readoff(f.data, j["data"])
        assert getattr(figures, key) is f


def check_fit_column(f, c):
    """A FitResult against its JSON column."""
    assert_fields(f, c, ("name", "n", "freq", "model", "model_structure", "objective", "status", "message",
                         "evaluations", "omega", "estimator", "efficiency", "alpha", "unit"))
    check_parameters(f.parameters, c["parameters"])
    check_gof(f.gof, c["gof"])
    assert list(f.notes) == c["notes"]
    assert f.quality.rejected == c["quality"]["rejected"]
    assert [w.level for w in f.quality.worst_levels] == [w["level"] for w in c["quality"]["worst_levels"]]
    assert_floats(f.implied_wv, c["implied_wv"], "implied_wv")
    check_wv_levels(f.levels, c["levels"])
    assert f.wv is f.levels.wv and f.tau is f.levels.tau
    check_continuous(f.continuous, c["continuous"])
    check_kalman(f.kalman, c["kalman"])
    check_allan(f.allan, c["allan"])
    check_noise_figures(f.noise_figures, c["noise_figures"])


def check_select_column(s, c):
    """A SelectColumn against its JSON column."""
    assert_fields(s, c, ("name", "n", "freq", "full_model", "best", "best_model", "penalty", "omega", "models",
                         "representation_violations", "not_converged", "failed", "all_rejected", "estimator", "unit"))
    assert len(s.ranking) == len(c["ranking"])
    for row, r in zip(s.ranking, c["ranking"]):
        assert_fields(row, r, ("rank", "model", "objective", "optimism", "criterion", "optimism_analytic",
                               "optimism_bootstrap", "optimism_bootstrap_se", "rank_analytic", "rank_bootstrap",
                               "gof_p_value", "status", "effective_parameters"))
        assert list(row.members) == r["members"] and list(row.reductions) == r["reductions"]
        assert_floats(row.member_objectives, r["member_objectives"], "member_objectives")
        check_parameters(row.parameters, r["parameters"])
    assert [(k.model, k.effective, k.status) for k in s.candidates] == \
        [(k["model"], k["effective"], k["status"]) for k in c["candidates"]]
    b = s.best_fit
    assert b.model == c["best_model"] and b.model_structure == c["best"]
    assert b.parameters == s.ranking[0].parameters  # rank 1 is the chosen model, with its intervals
    assert_same(b.objective, c["best_fit"]["objective"])
    check_gof(b.gof, c["best_fit"]["gof"])
    assert b.status == c["best_fit"]["status"] and list(b.notes) == c["best_fit"]["notes"]
    check_continuous(s.best_continuous, c["best_continuous"])
    check_kalman(s.best_kalman, c["best_kalman"])
    check_wv_levels(s.levels, c["levels"])
    check_allan(s.allan, c["allan"])
    check_noise_figures(s.noise_figures, c["noise_figures"])
