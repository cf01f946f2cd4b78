"""The Python module against the command-line program: same data, same options, the same
JSON numbers to the last bit; and its error path (gmwm.InputError, the CLI's message)."""
import csv
import gzip
import json
import os
import subprocess
import threading

import numpy as np
import pytest

import gmwm

SOURCE = os.environ.get("GMWM_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
CLI = os.environ.get("GMWM_CLI_PATH", os.path.join(SOURCE, "build", "gmwm"))
EXAMPLE = os.path.join(SOURCE, "data", "example_imu6.csv.gz")


def read_example():
    """The shipped example's columns, parsed by Python (correctly rounded, as the C++ reader)."""
    with gzip.open(EXAMPLE, "rt") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    return {name: np.array([float(r[i]) for r in body]) for i, name in enumerate(header)}


def cli_json(tmp_path, *args):
    out = tmp_path / "out.json"
    subprocess.run([CLI, *args, "--json", str(out), "--quiet"], check=True)
    return json.loads(out.read_text())


@pytest.fixture(scope="module")
def example():
    return read_example()


def test_the_module_reports_the_library_version():
    assert gmwm.__version__.count(".") == 2


def test_wv_equals_the_cli_json_bit_for_bit(tmp_path, example):
    doc = cli_json(tmp_path, "wv", EXAMPLE, "--columns", "gyro_x")
    col = doc["columns"][0]
    mine = gmwm.wv(example["gyro_x"], freq=col["freq"], name="gyro_x")
    assert mine["levels"] == col["levels"]
    assert mine["n"] == col["n"]


def test_allan_equals_the_cli_adev_json_bit_for_bit(tmp_path, example):
    doc = cli_json(tmp_path, "wv", EXAMPLE, "--columns", "gyro_y", "--adev", "--units", "gyro=rad/s")
    col = doc["columns"][0]
    mine = gmwm.allan(example["gyro_y"], freq=col["freq"], units="gyro=rad/s", name="gyro_y")
    assert col["allan"] and col["noise_figures"]
    for key in ("unit", "allan", "noise_figures"):
        assert mine[key] == col[key], key


def test_allan_refuses_a_missing_rate_and_bad_points_with_one_line(example):
    with pytest.raises(gmwm.InputError, match=r"^freq: found 0, expected a sampling rate in Hz from 1e-09 to 1e\+09"):
        gmwm.allan(example["gyro_y"], freq=0.0)
    with pytest.raises(gmwm.InputError, match="^points_per_octave: "):
        gmwm.allan(example["gyro_y"], freq=100.0, points_per_octave=0)


@pytest.mark.parametrize("baseline", [
    ["--model", "WN(sigma2=1e-6)+RW(gamma2=1e-12)"],
    ["--kalibr", os.path.join(SOURCE, "data", "adis16405_imu.yaml"), "--no-unit-check"],
    ["--datasheet", os.path.join(SOURCE, "data", "adis16405_datasheet.yaml"), "--no-unit-check"],
    ["--fit", "WN+RW"],
])
def test_gap_equals_the_cli_json_bit_for_bit(tmp_path, example, baseline):
    doc = cli_json(tmp_path, "gap", EXAMPLE, "--columns", "gyro_x,accel_y", "--replicates", "40", *baseline)
    kwargs = {"model": baseline[1]} if baseline[0] == "--model" else \
        {baseline[0][2:]: baseline[1], "unit_check": False} if "--no-unit-check" in baseline else {"fit": baseline[1]}
    mine = gmwm.gap(np.column_stack([example["gyro_x"], example["accel_y"]]), freq=doc["columns"][0]["freq"],
                    names=["gyro_x", "accel_y"], replicates=40, **kwargs)
    assert [c["headline"] for c in doc["columns"]]
    for key in ("baseline_source", "replicates", "seed", "cross_axis", "columns"):
        assert mine[key] == doc[key], key
    # The corrected configuration: the same fields and gap left (its text names the input).
    for key in ("format", "changes", "columns"):
        assert mine["corrected"][key] == doc["corrected"][key], key


def test_gap_refuses_two_baselines_and_a_bad_sensor_with_one_line(example):
    x = np.column_stack([example["gyro_x"]])
    with pytest.raises(gmwm.InputError, match="^gap: give exactly one baseline"):
        gmwm.gap(x, freq=100.0, model="WN(sigma2=1)", fit="WN")
    with pytest.raises(gmwm.InputError, match="^sensor: expected gyro or accel, got 'mag'"):
        gmwm.gap(x, freq=100.0, model="WN(sigma2=1)", sensor="mag")


def test_fit_equals_the_cli_json_bit_for_bit(tmp_path, example):
    doc = cli_json(tmp_path, "fit", EXAMPLE, "--columns", "accel_y", "--model", "AR1+WN+RW")
    col = doc["columns"][0]
    mine = gmwm.fit(example["accel_y"], "AR1+WN+RW", freq=col["freq"], name="accel_y")
    for key in ("model", "parameters", "objective", "gof", "status", "implied_wv", "levels", "unit", "continuous",
                "kalman", "allan", "noise_figures"):
        assert mine[key] == col[key], key


def test_select_equals_the_cli_json_bit_for_bit_on_two_columns(tmp_path, example):
    doc = cli_json(tmp_path, "select", EXAMPLE, "--columns", "gyro_z,accel_x", "--model", "AR1+WN+RW",
                   "--units", "gyro=rad/s,accel=m/s^2")
    data = np.column_stack([example["gyro_z"], example["accel_x"]])
    mine = gmwm.select(data, "AR1+WN+RW", freq=doc["columns"][0]["freq"], names=["gyro_z", "accel_x"],
                       units="gyro=rad/s,accel=m/s^2")
    assert len(mine) == 2
    for m, c in zip(mine, doc["columns"]):
        assert m["name"] == c["name"]
        assert c["noise_figures"] and c["best_kalman"]
        for key in ("best", "best_model", "ranking", "best_fit", "unit", "best_continuous", "best_kalman", "allan",
                    "noise_figures"):
            assert m[key] == c[key], key


def test_robust_fit_and_select_equal_the_cli_json_bit_for_bit(tmp_path, example):
    doc = cli_json(tmp_path, "fit", EXAMPLE, "--columns", "gyro_y", "--model", "AR1+WN+RW", "--robust", "--eff", "0.8")
    col = doc["columns"][0]
    mine = gmwm.fit(example["gyro_y"], "AR1+WN+RW", freq=col["freq"], name="gyro_y", robust=True, eff=0.8)
    for key in ("model", "parameters", "objective", "gof", "levels"):
        assert mine[key] == col[key], key
    doc = cli_json(tmp_path, "select", EXAMPLE, "--columns", "accel_z", "--model", "AR1+WN+RW", "--robust",
                   "--estimator", "bisquare")
    col = doc["columns"][0]
    mine = gmwm.select(example["accel_z"], "AR1+WN+RW", freq=col["freq"], names=["accel_z"], robust=True,
                       estimator="bisquare")[0]
    for key in ("best_model", "ranking", "levels"):
        assert mine[key] == col[key], key
    with pytest.raises(gmwm.InputError, match="eff: only meaningful with robust=True"):
        gmwm.fit(example["gyro_y"], "WN", eff=0.6)
    with pytest.raises(gmwm.InputError, match="unknown robust estimator 'tukey'"):
        gmwm.fit(example["gyro_y"], "WN", robust=True, estimator="tukey")


def test_simulate_equals_the_cli_series(tmp_path):
    out = tmp_path / "sim.csv"
    subprocess.run([CLI, "simulate", "--model", "AR1(phi=0.9,sigma2=1e-4)+RW(gamma2=1e-8)", "--n", "2000",
                    "--signals", "2", "--output", str(out), "--quiet"], check=True)
    with open(out) as f:
        rows = list(csv.reader(f))
    names = rows[0]
    cli = np.array([[float(v) for v in r] for r in rows[1:]])
    mine = gmwm.simulate("AR1(phi=0.9,sigma2=1e-4)+RW(gamma2=1e-8)", 2000, signals=2)
    assert mine.shape == (2000, 2)  # samples x signals, as the file's columns
    first = names.index(next(n for n in names if n != "time"))
    # The CSV carries the values to round-trip precision: the same doubles.
    np.testing.assert_array_equal(mine[:, 0], cli[:, first])
    np.testing.assert_array_equal(mine[:, 1], cli[:, first + 1])
    # ... and select() reads them as two columns.
    assert len(gmwm.select(mine, "WN+RW")) == 2


def test_bad_input_raises_input_error_with_the_cli_message(tmp_path, example):
    with pytest.raises(gmwm.InputError) as e:
        gmwm.fit(example["gyro_x"], "AR1+FOO")
    cli = subprocess.run([CLI, "fit", EXAMPLE, "--columns", "gyro_x", "--model", "AR1+FOO"], capture_output=True,
                         text=True)
    assert cli.returncode == 2
    assert str(e.value) in cli.stderr
    assert isinstance(e.value, ValueError)
    with pytest.raises(gmwm.InputError, match="sample 2 is not a finite number"):
        gmwm.wv(np.array([1.0, 2.0, np.nan] + [0.0] * 100))
    with pytest.raises(gmwm.InputError, match="expected a 1-D array"):
        gmwm.wv(np.zeros((4, 4, 4)))
    with pytest.raises(gmwm.InputError, match="found 10 samples, expected at least 16"):
        gmwm.wv(np.arange(10.0))
    with pytest.raises(gmwm.InputError, match="expected a 2-D array of numbers"):
        gmwm.select(np.array([["1", "a"]] * 100, dtype=object), "WN+RW")
    with pytest.raises(gmwm.InputError, match="found no column"):
        gmwm.select([], "WN+RW")
    with pytest.raises(gmwm.InputError, match="found no column"):
        gmwm.select(np.zeros((100, 0)), "WN+RW")
    with pytest.raises(gmwm.InputError, match="expected an array"):
        gmwm.select(1.0, "WN+RW")
    with pytest.raises(gmwm.InputError, match="^freq: found 0, expected a sampling rate in Hz"):
        gmwm.simulate("WN(sigma2=1)", 100, freq=0)


def test_a_units_typo_is_refused_by_every_function_with_the_clis_message(tmp_path, example):
    """One units convention (the CLI's --units), validated: a typo is never taken as a label."""
    x = example["gyro_x"]
    freq = 100.0
    bad = subprocess.run([CLI, "wv", EXAMPLE, "--adev", "--units", "dge/s", "--quiet"], capture_output=True, text=True)
    assert bad.returncode == 2
    cli_message = bad.stderr.strip().splitlines()[-1]
    assert "--units 'dge/s': expected one unit" in cli_message
    calls = [lambda: gmwm.allan(x, freq=freq, units="dge/s"),
             lambda: gmwm.fit(x, "WN+RW", freq=freq, units="dge/s"),
             lambda: gmwm.select(x, "WN+RW", freq=freq, units="dge/s"),
             lambda: gmwm.gap(x, freq=freq, model="WN(sigma2=1e-6)", units="dge/s", names=["gyro_x"]),
             lambda: gmwm.nav("truth", [], units="dge/s")]
    for call in calls:
        with pytest.raises(gmwm.InputError) as e:
            call()
        assert str(e.value) in cli_message
    with pytest.raises(gmwm.InputError, match="unit 'dge/s': expected rad/s, deg/s, deg/h"):
        gmwm.plan(model="WN(sigma2=1e-8)", freq=100.0, unit="dge/s")
    # A bare unit labels every column whose name tells no kind, as the CLI's --units does.
    assert gmwm.fit(x, "WN+RW", freq=freq, units="deg/s")["unit"] == "deg/s"
    assert gmwm.fit(x, "WN+RW", freq=freq, units="gyro=deg/s", name="gyro_x")["unit"] == "deg/s"
    assert gmwm.fit(x, "WN+RW", freq=freq, units="accel=g", name="gyro_x")["unit"] == "rad/s"


def test_a_constant_or_underflowing_series_is_refused_naming_it(example):
    # Issue 25: these came back "converged" at a parameter floor of 3.7e-44.
    with pytest.raises(gmwm.InputError, match="found all 1000 values equal to 1.5, expected a varying signal"):
        gmwm.fit(np.full(1000, 1.5), "WN")
    with pytest.raises(gmwm.InputError, match="found all 1000 values equal to 0"):
        gmwm.select(np.zeros(1000), "WN+RW")
    tiny = example["gyro_x"] * 1e-300
    for call in (lambda: gmwm.wv(tiny, name="gyro_x"), lambda: gmwm.fit(tiny, "WN+RW", name="gyro_x"),
                 lambda: gmwm.allan(tiny, freq=100.0)):
        with pytest.raises(gmwm.InputError, match="zero at every level although the values vary"):
            call()
    with pytest.raises(gmwm.InputError, match="column 'gyro_x': the wavelet variance at level"):
        gmwm.fit(example["gyro_x"] * 1e160, "WN+RW", name="gyro_x")


def test_computations_release_the_gil(example):
    # Two selections in threads finish with the same results as one after the other; while
    # they run, the interpreter keeps executing Python (a counter advances).
    data = example["gyro_x"]
    expected = gmwm.select(data, "2*AR1+WN+RW")[0]["ranking"]
    results, ticks, done = [], [0], threading.Event()

    def work():
        results.append(gmwm.select(data, "2*AR1+WN+RW")[0]["ranking"])

    def count():
        while not done.is_set():
            ticks[0] += 1

    counter = threading.Thread(target=count)
    counter.start()
    workers = [threading.Thread(target=work) for _ in range(2)]
    for w in workers:
        w.start()
    for w in workers:
        w.join()
    done.set()
    counter.join()
    assert results == [expected, expected]
    assert ticks[0] > 1000


def test_nav_equals_the_cli_json_bit_for_bit(tmp_path):
    sel = tmp_path / "sel.json"
    subprocess.run([CLI, "select", EXAMPLE, "--model", "AR1+WN+RW", "--units", "gyro=rad/s,accel=m/s^2", "--json",
                    str(sel), "--quiet"], check=True)
    kalibr = os.path.join(SOURCE, "data", "adis16405_imu.yaml")
    doc = cli_json(tmp_path, "nav", "--truth", str(sel), "--filter", "truth", "--filter", "wnrw*2", "--filter", kalibr,
                   "--outage", "120:180", "--horizon", "240", "--monte-carlo", "20")
    doc.pop("run")
    mine = gmwm.nav(str(sel), ["truth", "wnrw*2", kalibr], outages=[(120.0, 180.0)], horizon=240.0, monte_carlo=20)
    assert mine == doc
    assert mine["filters"][0]["verdict"] == "consistent"


def test_nav_refuses_a_bad_trajectory_and_source_with_the_clis_message(tmp_path):
    with pytest.raises(gmwm.InputError, match="^trajectory 'maneuver': expected static, constant-velocity or manoeuvre"):
        gmwm.nav("gyro=WN(sigma2=1e-6);accel=WN(sigma2=1e-4)", trajectory="maneuver", rate=100.0)
    with pytest.raises(gmwm.InputError, match=r"the inflation after '\*' must be a positive number"):
        gmwm.nav("gyro=WN(sigma2=1e-6);accel=WN(sigma2=1e-4)", ["truth*0"], rate=100.0)


def test_plan_equals_the_cli_json_bit_for_bit(tmp_path):
    doc = cli_json(tmp_path, "plan", "--model", "WN(sigma2=1e-8)+RW(gamma2=1e-14)", "--freq", "100", "--unit", "rad/s",
                   "--targets", "N,K", "--have", "3600")
    doc.pop("run")
    mine = gmwm.plan(model="WN(sigma2=1e-8)+RW(gamma2=1e-14)", freq=100.0, unit="rad/s", targets=["N", "K"], have=3600.0)
    assert mine == doc
    with pytest.raises(gmwm.InputError, match="has no random walk term"):
        gmwm.plan(model="WN(sigma2=1e-8)", freq=100.0, targets=["K"])


def test_gap_check_equals_the_cli_json_bit_for_bit_and_refuses_as_it_does(tmp_path):
    args = ["--cases", "1", "--n", "4096", "--replicates", "20", "--families", "STEP,DR", "--strengths", "8",
            "--no-null"]
    doc = cli_json(tmp_path, "gap-check", *args)
    mine = gmwm.gap_check(cases=1, n=4096, replicates=20, families="STEP,DR", strengths="8", null=False)
    doc.pop("run", None)
    mine.pop("run", None)
    assert mine == doc
    bad = subprocess.run([CLI, "gap-check", "--families", "STEP,XX", "--quiet"], capture_output=True, text=True)
    assert bad.returncode == 2
    with pytest.raises(gmwm.InputError) as e:
        gmwm.gap_check(families="STEP,XX")
    assert str(e.value) in bad.stderr
    with pytest.raises(gmwm.InputError, match="--strengths 'inf'"):
        gmwm.gap_check(strengths="inf")
