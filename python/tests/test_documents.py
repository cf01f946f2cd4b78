"""Documents of the command line that the module types without a binding of its own: the
joint fit (`gmwm fit --joint`), the joint selection (`gmwm select --joint`) and export,
loaded with from_json from the command's JSON: to_json() is the file's text, every typed
field holds the document's value."""
import dataclasses
import json
import os
import subprocess

import pytest

import gmwm
from typed_checks import (assert_fields, assert_floats, assert_text_is_the_document, check_continuous, check_gof,
                          check_kalman, check_noise_figures, check_parameters)

SOURCE = os.environ.get("GMWM_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
CLI = os.path.abspath(os.environ.get("GMWM_CLI_PATH", os.path.join(SOURCE, "build", "gmwm")))
EXAMPLE = os.path.join(SOURCE, "data", "example_imu6.csv.gz")
TRUTH = "AR1(phi=0.999,sigma2=1e-8)+WN(sigma2=1e-5)+RW(gamma2=1e-11)"


def run(cwd, *args):
    done = subprocess.run([CLI, *args, "--quiet"], cwd=cwd, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr


@pytest.fixture(scope="module")
def recordings(tmp_path_factory):
    """Three recordings (replicates) of a two-axis gyroscope, simulated by the command."""
    folder = tmp_path_factory.mktemp("replicates")
    for k in (1, 2, 3):
        run(folder, "simulate", "--model", TRUTH, "--n", "16384", "--freq", "100", "--signals", "2", "--names",
            "gyro_x,gyro_y", "--seed", str(k), "--output", f"day{k}.csv")
    return folder


def test_the_joint_fit_document_is_typed_from_the_clis_json(recordings):
    run(recordings, "fit", "day1.csv", "--joint", "day2.csv", "day3.csv", "--model", "AR1+WN+RW", "--units",
        "gyro=rad/s", "--json", "joint_fit.json")
    text = (recordings / "joint_fit.json").read_text()
    doc = json.loads(text)
    result = gmwm.JointFitResult.from_json(text)
    assert result.to_json() == text
    assert result.document == doc
    assert_fields(result, doc, ("input", "model_spec", "seed", "estimator"))
    assert [c.name for c in result.columns] == ["gyro_x", "gyro_y"]
    for typed, c in zip(result.columns, doc["columns"], strict=True):
        assert_text_is_the_document(typed, c)
        assert_fields(typed, c, ("name", "freq", "model", "model_structure", "objective", "status", "message", "unit"))
        check_parameters(typed.parameters, c["parameters"])
        check_gof(typed.gof, c["gof"])
        assert [r.source for r in typed.replicates] == [f"day{k}.csv:{c['name']}" for k in (1, 2, 3)]
        for r, j in zip(typed.replicates, c["replicates"], strict=True):
            assert_fields(r, j, ("source", "n", "levels", "objective_share"))
            assert_fields(r.fit, j["fit"], ("model", "status", "objective"))
            check_parameters(r.fit.parameters, j["fit"]["parameters"])
        assert_floats(typed.agmwm.value, [a["value"] for a in c["agmwm"]], "agmwm.value")
        assert_floats(typed.agmwm.se, [a["se"] for a in c["agmwm"]], "agmwm.se")
        boot = c["replicate_bootstrap"]
        assert_fields(typed.replicate_bootstrap, boot, ("method", "draws", "exhaustive"))
        assert_floats(typed.replicate_bootstrap.ci_low, boot["ci_low"], "ci_low")
        assert_floats(typed.replicate_bootstrap.ci_high, boot["ci_high"], "ci_high")
        test = c["replicate_test"]
        assert_fields(typed.replicate_test, test, ("heterogeneity", "heterogeneity_p_value", "statistic", "p_value",
                                                   "draws"))
        assert_floats(typed.replicate_test.own_minimum, test["own_minimum"], "own_minimum")
        check_continuous(typed.continuous, c["continuous"])
        check_kalman(typed.kalman, c["kalman"])
        assert typed.allan is None  # the replicates have no one data curve
        check_noise_figures(typed.noise_figures, c["noise_figures"])
        assert typed.noise_figures.N.unit == "rad/s/sqrt(Hz)"
        assert typed.parameter("phi").value == c["parameters"][0]["value"]
    assert "gyro_x" in repr(result) and "\n" not in repr(result.columns[0])


def test_the_joint_select_document_is_typed_from_the_clis_json(recordings):
    run(recordings, "select", "day1.csv", "--joint", "day2.csv", "day3.csv", "--model", "AR1+WN+RW", "--units",
        "gyro=rad/s", "--json", "joint_select.json")
    text = (recordings / "joint_select.json").read_text()
    doc = json.loads(text)
    result = gmwm.JointSelectResult.from_json(text)
    assert result.to_json() == text
    assert result.document == doc
    assert_fields(result, doc, ("input", "model_spec", "seed", "optimism", "estimator"))
    for typed, c in zip(result.columns, doc["columns"], strict=True):
        assert_text_is_the_document(typed, c)
        assert_fields(typed, c, ("name", "freq", "full_model", "chosen", "recommended", "chosen_analytic",
                                 "chosen_bootstrap", "all_rejected", "best_model", "unit"))
        assert list(typed.replicates) == c["replicates"]
        assert [list(s) for s in typed.training] == c["training"]
        for row, r in zip(typed.ranking, c["ranking"], strict=True):
            assert_fields(row, r, [f.name for f in dataclasses.fields(row) if f.name != "split_loss"])
            assert_floats(row.split_loss, r["split_loss"], "split_loss")
        best = typed.best_fit
        assert best.model == c["best_model"] and best.model_structure == c["best_fit"]["model"] == c["recommended"]
        assert_fields(best, c["best_fit"], ("status", "objective"))
        check_gof(best.gof, c["best_fit"]["gof"])
        assert best.quality is None and best.parameters == ()
        check_continuous(best.continuous, c["best_continuous"])
        check_kalman(best.kalman, c["best_kalman"])
        check_noise_figures(typed.noise_figures, c["noise_figures"])
        assert typed.noise_figures is best.noise_figures


@pytest.mark.parametrize("options", [
    ["--format", "kalibr", "--output", "imu.yaml"],
    ["--format", "kalibr", "--output", "imu.yaml", "--consistent-for", "20,60"],
    ["--format", "basalt", "--output", "calib.json", "--aggregate", "per-axis"],
])
def test_the_export_document_is_typed_from_the_clis_json(tmp_path, options):
    run(tmp_path, "select", EXAMPLE, "--model", "AR1+WN+RW", "--units", "gyro=rad/s,accel=m/s^2", "--json", "sel.json")
    run(tmp_path, "export", "sel.json", *options, "--json", "export.json")
    text = (tmp_path / "export.json").read_text()
    doc = json.loads(text)
    result = gmwm.ExportResult.from_json(text)
    assert result.to_json() == text
    assert result.document == doc
    assert_fields(result, doc, ("format", "output", "sidecar", "source", "aggregation", "inflate", "inflate_walk",
                                "rate"))
    assert list(result.warnings) == doc["warnings"]
    for typed, c in zip(result.columns, doc["columns"], strict=True):
        assert_fields(typed, c, ("name", "freq", "kind", "unit", "model", "noise_density", "random_walk"))
        assert [(m.correlation_time, m.sigma, m.drive) for m in typed.gauss_markov] == \
            [(m["correlation_time"], m["sigma"], m["drive"]) for m in c["gauss_markov"]]
    assert set(result.written) == set(doc["written"]) == {"gyro", "accel"}
    for kind, written in result.written.items():
        j = doc["written"][kind]
        assert list(written.columns) == j["columns"] and written.per_axis == j["per_axis"]
        assert_fields(written.combined, j["combined"], list(j["combined"]))
        if j["per_axis"]:
            assert set(written.axes) == {"x", "y", "z"}
            for axis, noise in written.axes.items():
                assert_fields(noise, j["axes"][axis], list(j["axes"][axis]))
        else:
            assert written.axes is None
    if "--consistent-for" in options:
        assert_fields(result.consistent_for, doc["consistent_for"], list(doc["consistent_for"]))
        assert result.inflate == doc["consistent_for"]["white_factor"]
    else:
        assert result.consistent_for is None
