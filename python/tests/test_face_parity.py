"""Python and the command line refuse the same bad values with the same words and accept the
same good ones with the same document (issue 45), over the one table the web app is held to
as well (tests/data/face_parity.json; tests/serve/face_parity_test.cc)."""
import json
import os

import numpy as np
import pytest

import gmwm
from cli_support import SOURCE, run

with open(os.path.join(SOURCE, "tests", "data", "face_parity.json")) as f:
    TABLE = json.load(f)
# The model every case without its own is run with, as in the C++ test.
MODEL = "WN+RW"
TRUTH = "AR1(phi=0.99,sigma2=1e-6)+WN(sigma2=1e-4)+RW(gamma2=1e-10)"


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    """gyro_x at 100 Hz, written as the CLI reads it; its samples as Python has them."""
    folder = tmp_path_factory.mktemp("parity")
    run(folder, "simulate", "--model", TRUTH, "--n", "16384", "--freq", "100", "--names", "gyro_x", "--output",
        "imu.csv", "--quiet")
    rows = np.loadtxt(folder / "imu.csv", delimiter=",", skiprows=1, ndmin=2)
    return folder, rows[:, -1]


def python_call(study, x, **kw):
    if study == "stability":
        return gmwm.stability(x, freq=100, names=["gyro_x"], **kw)
    model = kw.pop("model", None)
    if study == "fit":
        return gmwm.fit(x, model if model is not None else MODEL, freq=100, name="gyro_x", **kw)
    if "models" not in kw:
        kw["model"] = model if model is not None else MODEL
    return gmwm.select(x, freq=100, names=["gyro_x"], **kw)


@pytest.mark.parametrize("case", TABLE["refusals"], ids=lambda c: f"{c['study']} {c['option']} {c['value']}")
def test_python_refuses_every_bad_value_of_the_table_with_the_clis_words(recording, case):
    folder, x = recording
    args = [case["study"], "imu.csv", case["option"]] + ([case["value"]] if case["value"] is not None else [])  # a switch
    if case["option"] not in ("--model", "--models") and case["study"] != "stability":
        args += ["--model", MODEL]
    also = case.get("also", {})
    cli = run(folder, *args, *also, check=False)
    assert cli.returncode == 2, cli.stderr
    assert cli.stderr.strip().endswith(case["words"]), cli.stderr
    with pytest.raises(gmwm.InputError) as e:
        python_call(case["study"], x, **{case["field"]: case["json"]}, **{f[2:]: on for f, on in also.items()})
    said = str(e.value)
    assert said.endswith(case["words"]), f"python: {said}\nwords: {case['words']}"
    assert case["field"] in said and "--" not in said, said


@pytest.mark.parametrize("case", TABLE["reads"], ids=lambda c: f"read {c['option']} {c['value']}")
def test_gmwm_read_refuses_every_bad_read_of_the_table_with_the_clis_words(recording, case):
    folder, _ = recording
    cli = run(folder, "wv", "imu.csv", case["option"], case["value"], check=False)
    assert cli.returncode == 2, cli.stderr
    assert case["words"] in cli.stderr, cli.stderr
    with pytest.raises(gmwm.InputError) as e:
        gmwm.read(folder / "imu.csv", **{case["field"]: case["json"]})
    said = str(e.value)
    assert case["words"] in said, f"python: {said}\nwords: {case['words']}"
    assert case["field"] in said and "--" not in said, said


@pytest.mark.parametrize("case", TABLE["acceptances"], ids=lambda c: f"{c['study']} {c['json']}")
def test_python_accepts_every_good_value_of_the_table_with_the_clis_document(recording, case):
    folder, x = recording
    # The rate Python is given (the CLI would estimate it from the stamps, to 2e-14).
    args = [case["study"], "imu.csv", "--freq", "100"]
    for option, value in case["options"].items():
        args += [option, value]
    cli = json.loads(run(folder, *args, "--json", "-", "--quiet").stdout)
    mine = python_call(case["study"], x, **case["json"])
    expected = cli["columns"][0] if case["study"] == "fit" else cli["columns"]
    got = json.loads(mine.to_json())
    assert (got["columns"] if case["study"] == "stability" else got) == expected
