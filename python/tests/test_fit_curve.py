"""gmwm.fit_curve (issue 48, item 5): a model fitted to a given Allan deviation curve in Python,
the command's document for the same file, named columns and a DataFrame read as the file is, and
the refusals in Python's words."""
import json
import warnings

import numpy as np
import pytest

import gmwm
from cli_support import run

TRUTH = "AR1(phi=0.995,sigma2=3e-4)+WN(sigma2=1)+RW(gamma2=1e-7)"


@pytest.fixture(scope="module")
def adev_csv(tmp_path_factory):
    """A record of the truth (2^16 samples at 100 Hz, seed 48) and its Allan deviation as `gmwm wv
    --adev-csv` writes it."""
    folder = tmp_path_factory.mktemp("curve")
    run(folder, "simulate", "--model", TRUTH, "--n", "65536", "--freq", "100", "--names", "gyro_x", "--seed", "48",
        "--output", "rec.csv", "--quiet")
    run(folder, "wv", "rec.csv", "--adev", "--adev-csv", "adev.csv", "--quiet")
    return folder / "adev.csv"


def test_a_curve_fit_is_the_commands_column_for_the_same_file(adev_csv):
    f = gmwm.fit_curve(adev_csv, "WN+RW+AR1", units="rad/s", exclude_taus=[(None, 0.015)])
    assert isinstance(f, gmwm.FitResult) and isinstance(f.curve, gmwm.CurveInfo)
    assert f.curve.value == "adev" and f.curve.weights == "edf" and f.curve.rate == "curve"
    assert f.curve.excluded == ":0.015" and not f.curve.fitted[0] and f.curve.fitted[1:].all()
    assert f.freq == 100.0 and f.estimator == "curve" and f.unit == "rad/s"
    assert np.isnan(f.gof.p_value) and f.gof.method.startswith("none (a given curve")
    assert f.noise_figures.N.value > 0 and len(f.implied_wv) == len(f.curve.tau)
    cli = json.loads(run(adev_csv.parent, "fit", "--curve", "adev.csv", "--model", "WN+RW+AR1", "--units", "rad/s",
                         "--exclude-taus", ":0.015", "--json", "-").stdout)
    column = cli["columns"][0]
    column["curve"]["source"] = f.curve.source  # the command was given the file's name, Python its path
    assert column == f.document


def test_named_columns_and_a_dataframe_fit_as_the_file_does(adev_csv):
    from_file = gmwm.fit_curve(adev_csv, "WN+RW+AR1")
    rows = [line.split(",") for line in adev_csv.read_text().splitlines()[1:]]
    columns = {name: np.array([float(r[k]) for r in rows]) for k, name in
               [(2, "tau_seconds"), (3, "adev"), (4, "ci_low"), (5, "ci_high"), (6, "edf")]}
    from_dict = gmwm.fit_curve(columns, "WN+RW+AR1", column="gyro_x")
    assert from_dict.name == "gyro_x" and from_dict.curve.source == "curve"
    assert from_dict.parameters[0].value == from_file.parameters[0].value
    assert [p.value for p in from_dict.parameters] == [p.value for p in from_file.parameters]
    pd = pytest.importorskip("pandas")
    from_frame = gmwm.fit_curve(pd.DataFrame(columns), "WN+RW+AR1")
    assert [p.value for p in from_frame.parameters] == [p.value for p in from_file.parameters]


def test_a_curve_without_intervals_is_weighed_as_the_shortest_record_and_warns():
    tau = 0.01 * 2.0 ** np.arange(10)
    avar = 2.0 / (tau * 100.0)  # white noise: sigma2 = 2 at 100 Hz
    with pytest.warns(UserWarning, match="no interval, edf or record length: weighed as the shortest record"):
        f = gmwm.fit_curve({"tau": tau, "avar": avar}, "WN")
    assert f.curve.weights == "shortest-record" and f.parameters[0].value == pytest.approx(2.0, rel=1e-9)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        g = gmwm.fit_curve({"tau": tau, "avar": avar}, "WN", record=100.0)
    assert g.curve.weights == "record" and g.curve.record_seconds == 100.0
    assert g.parameters[0].ci_high - g.parameters[0].ci_low < f.parameters[0].ci_high - f.parameters[0].ci_low


def test_refusals_name_the_point_and_pythons_keywords():
    tau = [0.01, 0.02, 0.02, 0.04]
    with pytest.raises(gmwm.InputError, match=r"curve: tau\[2\]: found tau 0.02 s again \(tau\[1\]\), expected each"):
        gmwm.fit_curve({"tau": tau, "adev": [1, 1, 1, 1]}, "WN")
    with pytest.raises(gmwm.InputError, match=r"curve: adev\[1\]: found nan, expected a positive finite adev"):
        gmwm.fit_curve({"tau": [0.01, 0.02], "adev": [1, float("nan")]}, "WN")
    good = {"tau": [0.01, 0.02, 0.04], "value": [1.0, 0.5, 0.25]}
    with pytest.raises(gmwm.InputError, match="expected value adev, avar or wv to say what it holds"):
        gmwm.fit_curve(good, "WN")
    with pytest.raises(gmwm.InputError, match=r"^omega: found 'full', expected model or diag"):
        gmwm.fit_curve(good, "WN", value="avar", omega="full")
    with pytest.raises(gmwm.InputError, match=r"^record: found 0.01 s, expected at least the longest window"):
        gmwm.fit_curve(good, "WN", value="avar", record=0.01)
    with pytest.raises(gmwm.InputError, match=r"^exclude_taus: found '2:1', expected taus in seconds"):
        gmwm.fit_curve(good, "WN", value="avar", exclude_taus="2:1")
    with pytest.raises(gmwm.InputError, match=r"^value: found 'dev', expected adev, avar or wv"):
        gmwm.fit_curve(good, "WN", value="dev")
    with pytest.raises(gmwm.InputError, match="curve: expected a curve file's path or named columns"):
        gmwm.fit_curve([1, 2, 3], "WN")
