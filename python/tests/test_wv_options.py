"""gmwm.wv takes what `gmwm wv` takes (issue 45: Python lacked the robust WV, --units and
--adev): the same study (pipeline::study_wv) and document, so each column equals the
command's on the same file, and a bad value is refused naming Python's keyword."""
import json

import numpy as np
import pytest

import gmwm
from cli_support import run
from test_read import RATE, write_csv

N = 8192


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    folder = tmp_path_factory.mktemp("wv_options")
    x = gmwm.simulate("WN(sigma2=1e-4)+RW(gamma2=1e-9)", N, freq=RATE, signals=1, seed=21).reshape(-1, 1).copy()
    x[::97] += 0.3  # outliers: the robust WV's contamination diagnostic has something to say
    write_csv(folder / "imu.csv", x, names=("gyro_x",))
    return folder, gmwm.read(folder / "imu.csv")


def cli_column(folder, *args):
    return json.loads(run(folder, "wv", "imu.csv", *args, "--json", "-", "--quiet").stdout)["columns"][0]


@pytest.mark.parametrize("python,cli", [
    ({}, []),
    ({"robust": True}, ["--robust"]),
    ({"robust": True, "eff": 0.8, "estimator": "bisquare"}, ["--robust", "--eff", "0.8", "--estimator", "bisquare"]),
    ({"robust": True, "levels": 9, "spike_screen": False}, ["--robust", "--levels", "9", "--no-spike-screen"]),
    ({"adev": True, "units": "deg/s"}, ["--adev", "--units", "deg/s"]),
    ({"adev": True, "adev_points": 2, "levels": 8}, ["--adev", "--adev-points", "2", "--levels", "8"]),
    ({"units": "gyro=deg/s,accel=g"}, ["--units", "gyro=deg/s,accel=g"]),
    ({"robust": True, "units": "rad/s"}, ["--robust", "--units", "rad/s"]),
], ids=["classical", "robust", "robust bisquare", "robust levels unscreened", "adev with units",
        "adev points and levels", "units", "robust units"])
def test_wv_gives_the_commands_column_for_each_of_its_options(recording, python, cli):
    folder, rec = recording
    w = gmwm.wv(rec, **python)
    assert w.document == cli_column(folder, *cli)
    if python.get("robust"):
        assert w.levels.classical_wv is not None and w.estimator != "classical"
    if python.get("adev"):
        assert w.allan is not None and w.noise_figures is not None


@pytest.mark.parametrize("kw,words", [
    ({"eff": 0.8}, "eff 0.8: only meaningful with robust=True"),
    ({"robust": True, "estimator": "tukey"}, "estimator: "),
    ({"units": "furlong"}, "units 'furlong'"),
    ({"adev": True, "adev_points": 0}, "adev_points: "),
    ({"spike_screen": False}, "spike_screen=False: only meaningful with robust=True"),
])
def test_a_bad_wv_option_is_refused_naming_its_keyword(recording, kw, words):
    _, rec = recording
    with pytest.raises(gmwm.InputError) as e:
        gmwm.wv(rec, **kw)
    assert str(e.value).startswith(words) and "--" not in str(e.value), str(e.value)


@pytest.mark.parametrize("python,cli", [
    ({"levels": 9}, ["--levels", "9"]),
    ({"kf_rate": 50}, ["--kf-rate", "50"]),
    ({"max_evaluations": 40}, ["--max-evaluations", "40"]),
    ({"robust": True, "levels": 10}, ["--robust", "--levels", "10"]),
], ids=["levels", "kf_rate", "max_evaluations", "robust levels"])
def test_fit_and_select_take_the_commands_levels_kalman_rate_and_evaluations(recording, python, cli):
    folder, rec = recording
    f = gmwm.fit(rec, "WN+RW", **python)
    command = json.loads(run(folder, "fit", "imu.csv", "--model", "WN+RW", *cli, "--json", "-", "--quiet").stdout)
    assert f.document == command["columns"][0]
    s = gmwm.select(rec, "WN+RW", **python)
    command = json.loads(run(folder, "select", "imu.csv", "--model", "WN+RW", *cli, "--json", "-", "--quiet").stdout)
    assert [c.document for c in s] == command["columns"]


@pytest.mark.parametrize("kw,words", [
    ({"levels": 20}, "levels 20: the signals have 8192 samples, which give at most 13 levels"),
    ({"kf_rate": 0}, "kf_rate: found 0, expected a sampling rate in Hz"),
    ({"max_evaluations": 5}, "max_evaluations must be at least 10"),
])
def test_a_bad_fit_option_is_refused_naming_its_keyword(recording, kw, words):
    _, rec = recording
    for call in (gmwm.fit, gmwm.select):
        with pytest.raises(gmwm.InputError) as e:
            call(rec, "WN+RW", **kw)
        assert words in str(e.value) and "--" not in str(e.value), str(e.value)


@pytest.mark.parametrize("python,cli", [
    ({"levels": 9, "kf_rate": 50}, ["--levels", "9", "--kf-rate", "50"]),
    ({"max_evaluations": 40}, ["--max-evaluations", "40"]),
], ids=["levels and kf_rate", "max_evaluations"])
def test_the_joint_functions_take_the_commands_levels_kalman_rate_and_evaluations(recording, python, cli):
    folder, rec = recording
    other = gmwm.read(write_csv(folder / "other.csv", rec.values[::-1].copy(), names=("gyro_x",)))
    joint = ["--joint", "other.csv"]
    f = gmwm.fit_joint([rec, other], "WN+RW", test_draws=19, **python)
    command = json.loads(run(folder, "fit", "imu.csv", *joint, "--model", "WN+RW", "--replicates", "19", *cli,
                             "--json", "-", "--quiet").stdout)
    assert unsourced(f.document["columns"]) == unsourced(command["columns"])
    s = gmwm.select_joint([rec, other], "WN+RW", **python)
    command = json.loads(run(folder, "select", "imu.csv", *joint, "--model", "WN+RW", *cli, "--json", "-",
                             "--quiet").stdout)
    assert unsourced(s.document["columns"]) == unsourced(command["columns"])


def unsourced(document):
    """The document without the names of its recordings (Python's "replicates[k]:gyro_x", the
    command's "FILE:gyro_x"): every number and every other text compared."""
    if isinstance(document, dict):
        return {k: unsourced(v) for k, v in document.items() if k != "source"
                and not (k == "replicates" and all(isinstance(r, str) for r in v))}
    if isinstance(document, list):
        return [unsourced(v) for v in document]
    return document


def test_a_wv_states_the_units_it_was_given_and_its_plot_labels_the_variance_with_them(recording):
    # A WV without --adev dropped the unit it was given: its plot said "wavelet variance" bare.
    folder, rec = recording
    assert cli_column(folder, "--units", "deg/s")["unit"] == "deg/s"
    assert "unit" not in cli_column(folder)
    w = gmwm.wv(rec, units="gyro=deg/s,accel=g")
    assert w.unit == "deg/s" and gmwm.wv(rec).unit is None
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    assert w.plot().get_ylabel() == "wavelet variance [(deg/s)^2]"
