"""Every key of every document the library writes has its typed field in Python (issue 45:
the result schema lived in four places and nothing checked that a new JSON key reached the
Python types).

The walk pairs a document with its typed result: an object's key is an attribute of the
typed object (or a key of a typed mapping), a list of objects is a tuple of typed objects of
the same length, or a columnar type (WvLevels: each row's key an array attribute), a
document whose top level is a list of columns is the result's `columns`, and a mapping keyed
by numbers (gap-check's strengths) is typed with float keys. A few keys are typed under
another shape, listed in TYPED_AS with the fields that carry them. A key without a field
fails, named by its path in the document.
"""
import os

import numpy as np
import pytest

import gmwm
from cli_support import SOURCE, run

TRUTH = "AR1(phi=0.999,sigma2=1e-8)+WN(sigma2=1e-5)+RW(gamma2=1e-11)"


# Keys typed under another shape: (type, key) -> the fields that carry the key's content.
TYPED_AS = {
    ("NavResult", "truth"): ("truth_source", "truth_models"),
    ("NavResult", "columns"): ("filters",),  # nav's results are per filter; its columns are empty
    ("GapCheckResult", "columns"): ("case_list",),  # per case; its columns are empty
    ("Attribution", "step_details"): ("steps",),  # GapStep.detail, .drop, .share of each step
    ("Attribution", "step_drops"): ("steps",),
    ("Attribution", "step_shares"): ("steps",),
    ("JointFitResult", "joint"): (),  # the type says it
    ("JointSelectResult", "joint"): (),
}


def untyped_keys(typed, document, path):
    """The paths of the document's keys that have no typed field under `typed`."""
    missing = []
    if isinstance(document, list) and hasattr(typed, "columns") and not isinstance(typed, (tuple, list)):
        return untyped_keys(typed.columns, document, path)
    if isinstance(document, dict):
        for key, value in document.items():
            where = f"{path}.{key}"
            if isinstance(typed, dict):
                number = numeric(key)
                if key in typed:
                    missing += untyped_keys(typed[key], value, where)
                elif number is not None and number in typed:
                    missing += untyped_keys(typed[number], value, where)
                else:
                    missing.append(where)
            elif (type(typed).__name__, key) in TYPED_AS:
                missing += [f"{where} (as {f})" for f in TYPED_AS[(type(typed).__name__, key)] if not hasattr(typed, f)]
            elif typed is None or not hasattr(typed, key):
                missing.append(where)
            else:
                missing += untyped_keys(getattr(typed, key), value, where)
    elif isinstance(document, list) and document and isinstance(document[0], dict):
        if isinstance(typed, (tuple, list)):
            if len(typed) != len(document):
                return [f"{path} ({len(typed)} typed for {len(document)})"]
            for k, (t, d) in enumerate(zip(typed, document)):
                missing += untyped_keys(t, d, f"{path}[{k}]")
        else:  # columnar: every row's key an array attribute
            keys = list(dict.fromkeys(k for row in document for k in row))
            missing += [f"{path}[].{k}" for k in keys if not hasattr(typed, k)]
    return missing


def numeric(key):
    try:
        return float(key)
    except ValueError:
        return None


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    """One result of every study of the module, on simulated data at fixed seeds."""
    folder = tmp_path_factory.mktemp("every_key")
    x = gmwm.simulate(TRUTH, 2**14, seed=3, signals=3, freq=100)
    names = ["gyro_x", "gyro_y", "gyro_z"]
    out = {
        "wv": gmwm.wv(x[:, 0], freq=100),
        "allan": gmwm.allan(x[:, 0], freq=100, units="gyro=rad/s"),
        "fit": gmwm.fit(x[:, 0], "AR1+WN+RW", freq=100, units="gyro=rad/s"),
        "fit robust": gmwm.fit(x[:, 0], "AR1+WN+RW", freq=100, robust=True),
        "select": gmwm.select(x, "AR1+WN+RW", freq=100, names=names, units="gyro=rad/s"),
        "select robust": gmwm.select(x[:, 0], "AR1+WN+RW", freq=100, robust=True),
        "gap": gmwm.gap(x[:, :1], freq=100, model=TRUTH, names=["gyro_x"], replicates=40),
        "plan": gmwm.plan(model="WN(sigma2=1e-8)+RW(gamma2=1e-14)", freq=100, unit="rad/s"),
        "gap_check": gmwm.gap_check(cases=1, n=16384, replicates=40, families="QN,STEP"),
    }
    # nav reads a command's document: the CLI's select of the shipped six-axis example.
    run(folder, "select", os.path.join(SOURCE, "data", "example_imu6.csv.gz"), "--model", "WN+RW", "--units",
        "gyro=rad/s,accel=m/s^2", "--json",
        "select.json", "--quiet")
    out["nav"] = gmwm.nav(os.path.join(folder, "select.json"), ["truth", "wnrw*2"], horizon=60.0)
    out["export"] = gmwm.export(out["select"], format="kalibr", partial=True)
    reps = [gmwm.simulate(TRUTH, 2**14, seed=k, signals=2, freq=100) for k in (1, 2, 3)]
    out["fit_joint"] = gmwm.fit_joint(reps, "AR1+WN+RW", freq=100, names=names[:2], units="gyro=rad/s")
    out["select_joint"] = gmwm.select_joint(reps, "AR1+WN+RW", freq=100, names=names[:2], units="gyro=rad/s")
    a = out["allan"].allan
    out["fit_curve"] = gmwm.fit_curve({"tau": a.tau, "adev": a.adev, "ci_low": a.ci_low, "ci_high": a.ci_high},
                                      "AR1+WN+RW", units="rad/s", exclude_taus=":0.015")
    return out


@pytest.mark.parametrize("study", ["wv", "allan", "fit", "fit robust", "select", "select robust", "gap", "plan",
                                   "gap_check", "nav", "export", "fit_joint", "select_joint", "fit_curve"])
def test_every_key_of_the_document_has_its_typed_field(results, study):
    result = results[study]
    assert untyped_keys(result, result.document, study) == []


def test_the_walk_finds_a_key_without_a_field():
    # The checker's check: a key added to a document is reported with its path.
    x = gmwm.simulate("WN(sigma2=1)", 4096, seed=1)
    result = gmwm.fit(x, "WN", freq=100)
    document = dict(result.document) if isinstance(result.document, dict) else {"columns": result.document}
    document["a_new_key"] = 1
    assert "fit.a_new_key" in untyped_keys(result, document, "fit")
    assert np.isfinite(result.parameters[0].value)
