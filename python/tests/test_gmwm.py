"""The Python module against the command-line program: same data, same options, the same
JSON to the last bit (to_json() is the command's text), typed fields holding the document's
values; and its error path (gmwm.InputError, the CLI's message)."""
import csv
import dataclasses
import gzip
import inspect
import json
import math
import os
import subprocess
import threading

import numpy as np
import pytest

import gmwm
from gmwm._json_text import item_texts, member_text
from typed_checks import (assert_fields, assert_floats, assert_text_is_the_document, check_allan,
                          check_continuous, check_fit_column, check_noise_figures, check_parameters,
                          check_select_column, check_wv_levels)

SOURCE = os.environ.get("GMWM_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
CLI = os.path.abspath(os.environ.get("GMWM_CLI_PATH", os.path.join(SOURCE, "build", "gmwm")))
EXAMPLE = os.path.join(SOURCE, "data", "example_imu6.csv.gz")


def read_example():
    """The shipped example's columns, parsed by Python (correctly rounded, as the C++ reader)."""
    with gzip.open(EXAMPLE, "rt") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    return {name: np.array([float(r[i]) for r in body]) for i, name in enumerate(header)}


def cli_text(tmp_path, *args):
    """The JSON text the command writes."""
    out = tmp_path / "out.json"
    subprocess.run([CLI, *args, "--json", str(out), "--quiet"], check=True)
    return out.read_text()


def cli_json(tmp_path, *args):
    return json.loads(cli_text(tmp_path, *args))


def cli_column_texts(text):
    """The command's "columns", each as the library renders it alone (the same bytes)."""
    return item_texts(member_text(text, "columns"))


@pytest.fixture(scope="module")
def example():
    return read_example()


def test_the_module_reports_the_library_version():
    assert gmwm.__version__.count(".") == 2


def test_wv_equals_the_cli_json_bit_for_bit_and_types_its_levels(tmp_path, example):
    text = cli_text(tmp_path, "wv", EXAMPLE, "--columns", "gyro_x")
    col = json.loads(text)["columns"][0]
    mine = gmwm.wv(example["gyro_x"], freq=col["freq"], name="gyro_x")
    assert isinstance(mine, gmwm.WvResult)
    assert_text_is_the_document(mine, col)
    assert mine.to_json() == cli_column_texts(text)[0]
    assert_fields(mine, col, ("name", "n", "freq", "estimator", "efficiency", "alpha"))
    check_wv_levels(mine.levels, col["levels"])
    assert_floats(mine.tau, [lv["tau"] for lv in col["levels"]], "tau")
    assert_floats(mine.wv, [lv["wv"] for lv in col["levels"]], "wv")
    assert mine.allan is None and mine.noise_figures is None and mine.unit is None
    # The CLI's --adev column loads the same way, with its Allan deviation and figures.
    text = cli_text(tmp_path, "wv", EXAMPLE, "--columns", "gyro_x", "--adev", "--units", "gyro=deg/s")
    col = json.loads(text)["columns"][0]
    typed = gmwm.WvResult.from_json(cli_column_texts(text)[0])
    assert typed.unit == "deg/s"
    check_allan(typed.allan, col["allan"])
    check_noise_figures(typed.noise_figures, col["noise_figures"])


def test_a_robust_wv_column_types_its_diagnostics(tmp_path):
    text = cli_text(tmp_path, "wv", EXAMPLE, "--columns", "accel_y", "--robust")
    col = json.loads(text)["columns"][0]
    typed = gmwm.WvResult.from_json(cli_column_texts(text)[0])
    assert_text_is_the_document(typed, col)
    assert typed.estimator == "huber" and typed.efficiency == col["efficiency"]
    check_wv_levels(typed.levels, col["levels"])
    assert typed.levels.contaminated.dtype == bool
    assert typed.small_sample == col["small_sample"] and typed.quantization == col["quantization"]


def test_allan_equals_the_cli_adev_json_bit_for_bit_and_types_n_k_b(tmp_path, example):
    doc = cli_json(tmp_path, "wv", EXAMPLE, "--columns", "gyro_y", "--adev", "--units", "gyro=rad/s")
    col = doc["columns"][0]
    mine = gmwm.allan(example["gyro_y"], freq=col["freq"], units="gyro=rad/s", name="gyro_y")
    assert col["allan"] and col["noise_figures"]
    assert_text_is_the_document(mine, {key: col[key] for key in ("unit", "allan", "noise_figures")})
    assert mine.unit == "rad/s"
    check_allan(mine.allan, col["allan"])
    assert mine.tau is mine.allan.tau and mine.adev is mine.allan.adev
    check_noise_figures(mine.noise_figures, col["noise_figures"])
    assert (mine.noise_figures.N.unit, mine.noise_figures.K.unit, mine.noise_figures.B.unit) == (
        col["noise_figures"]["white"]["unit"], col["noise_figures"]["walk"]["unit"],
        col["noise_figures"]["instability"]["unit"])
    assert mine.noise_figures.N.how == col["noise_figures"]["white"]["how"]


def test_q_and_r_are_typed_beside_n_k_b_and_none_in_a_document_written_before_them():
    # QN(Q2 = 1) at 100 Hz: Q = sqrt(Q2) / f = 0.01 rad (the angle quantum of a rad/s gyro),
    # under white noise; no -1 or +1 slope beyond: R is only bounded.
    x = gmwm.simulate("QN(Q2=1)+WN(sigma2=0.01)", 2**18, freq=100, seed=4803)
    a = gmwm.allan(x, freq=100, units="rad/s")
    q, r = a.noise_figures.Q, a.noise_figures.R
    assert a.noise_figures.quantization is q and a.noise_figures.ramp is r
    assert (q.unit, r.unit) == ("rad", "rad/s^2")
    assert q.status in ("read", "extrapolated") and abs(q.value / 0.01 - 1) < 0.05
    assert r.status == "bound" and r.source == "bound" and math.isnan(r.low)
    assert "Q=" in repr(a.noise_figures) and "R=" in repr(a.noise_figures)
    assert gmwm._gmwm.figure_units("deg/s") == ("deg/s/sqrt(Hz)", "deg/s^2/sqrt(Hz)", "deg/s", "deg", "deg/s^2")
    # A document of an older gmwm: no "quantization" or "ramp", still read.
    old = json.loads(a.to_json())["noise_figures"]
    del old["quantization"], old["ramp"]
    typed = gmwm.NoiseFigures.from_dict(old)
    assert typed.Q is None and typed.R is None and typed.N.value == a.noise_figures.N.value
    assert "Q=" not in repr(typed)


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
def test_gap_equals_the_cli_json_bit_for_bit_and_types_each_column(tmp_path, example, baseline):
    # The same request on both faces: a record of these two columns (with --columns on the
    # six-column example, the CLI's record also holds axes the run left out, and a corrected
    # Kalibr or datasheet figure shared with them is kept; docs/gap.md, "Edited in place").
    two = tmp_path / "two.csv"
    with gzip.open(EXAMPLE, "rt") as f, open(two, "w", newline="") as out:
        rows = csv.reader(f)
        header = next(rows)
        keep = [header.index("time"), header.index("gyro_x"), header.index("accel_y")]
        w = csv.writer(out)
        w.writerow([header[i] for i in keep])
        for r in rows:
            w.writerow([r[i] for i in keep])
    doc = cli_json(tmp_path, "gap", str(two), "--replicates", "40", *baseline)
    kwargs = {"model": baseline[1]} if baseline[0] == "--model" else \
        {baseline[0][2:]: baseline[1], "unit_check": False} if "--no-unit-check" in baseline else {"fit": baseline[1]}
    mine = gmwm.gap(np.column_stack([example["gyro_x"], example["accel_y"]]), freq=doc["columns"][0]["freq"],
                    names=["gyro_x", "accel_y"], replicates=40, **kwargs)
    assert isinstance(mine, gmwm.GapResult)
    assert [c["headline"] for c in doc["columns"]]
    mine_doc = json.loads(mine.to_json())
    assert mine.document == mine_doc
    for key in ("baseline_source", "replicates", "seed", "cross_axis", "columns"):
        assert mine_doc[key] == doc[key], key
    # The corrected configuration: the same fields and gap left (its text names the input).
    for key in ("format", "changes", "columns"):
        assert mine_doc["corrected"][key] == doc["corrected"][key], key
    assert_fields(mine, doc, ("baseline_source", "replicates", "seed"))
    assert mine.cross_axis.tested == doc["cross_axis"]["tested"]
    for typed, c in zip(mine.columns, doc["columns"], strict=True):
        assert json.loads(typed.to_json()) == c
        assert_fields(typed, c, ("name", "n", "freq", "baseline_model", "headline"))
        g = c["gap"]
        assert_fields(typed.gap, g, ("detected", "p_value", "statistic", "window_length_seconds"))
        for key in ("tau", "tau_seconds", "ratio", "z", "ref_low", "ref_high", "analytic_low", "analytic_high"):
            assert_floats(getattr(typed.gap.levels, key), [lv[key] for lv in g["levels"]], key)
        assert typed.gap.levels.outside.tolist() == [lv["outside"] for lv in g["levels"]]
        assert [(b.direction, b.tau_from_seconds, b.tau_to_seconds, b.peak_ratio) for b in typed.gap.bands] == \
            [(b["direction"], b["tau_from_seconds"], b["tau_to_seconds"], b["peak_ratio"]) for b in g["bands"]]
        a = c["attribution"]
        assert typed.effect == a["effect"] and typed.attribution.model == a["model"]
        assert [s.effect for s in typed.attribution.steps] == a["steps"]
        assert [s.detail for s in typed.attribution.steps] == a["step_details"]
        assert_floats(np.array([s.share for s in typed.attribution.steps]), a["step_shares"], "step_shares")
        check_parameters(typed.attribution.parameters, a["parameters"])
        check_continuous(typed.attribution.physical, a["physical"])
        assert [k.effect for k in typed.attribution.candidates] == [k["effect"] for k in a["candidates"]]
        assert typed.closed == c["remaining"]["closed"]
        assert_fields(typed.shrinkage, c["shrinkage"], [f.name for f in dataclasses.fields(typed.shrinkage)])
        assert_fields(typed.navigation, c["navigation"], ("horizon_seconds", "rms_without", "rms_with", "unit"))
    corrected = mine.corrected
    assert corrected.format == doc["corrected"]["format"]
    for typed, c in zip(corrected.changes, doc["corrected"]["changes"], strict=True):
        assert_fields(typed, c, ("field", "input", "corrected", "unit", "changed"))
    for typed, c in zip(corrected.columns, doc["corrected"]["columns"], strict=True):
        assert (typed.name, typed.expressible, typed.full) == (c["name"], c["expressible"], c["full"])
        for which, assessment in typed.gap_left.items():
            assert_fields(assessment, c["gap_left"][which], ("objective", "levels_outside", "p_value"))


def test_gap_refuses_two_baselines_and_a_bad_sensor_with_one_line(example):
    x = np.column_stack([example["gyro_x"]])
    with pytest.raises(gmwm.InputError, match="^gap: give exactly one baseline"):
        gmwm.gap(x, freq=100.0, model="WN(sigma2=1)", fit="WN")
    with pytest.raises(gmwm.InputError, match="^sensor: found 'mag', expected gyro or accel$"):
        gmwm.gap(x, freq=100.0, model="WN(sigma2=1)", sensor="mag")




def test_fit_equals_the_cli_json_bit_for_bit_and_types_every_field(tmp_path, example):
    text = cli_text(tmp_path, "fit", EXAMPLE, "--columns", "accel_y", "--model", "AR1+WN+RW", "--units", "accel=g")
    col = json.loads(text)["columns"][0]
    mine = gmwm.fit(example["accel_y"], "AR1+WN+RW", freq=col["freq"], name="accel_y", units="accel=g")
    assert isinstance(mine, gmwm.FitResult)
    assert_text_is_the_document(mine, col)
    assert mine.to_json() == cli_column_texts(text)[0]
    check_fit_column(mine, col)
    assert mine.unit == "g"
    assert [p.unit for p in mine.continuous] == [p["unit"] for p in col["continuous"]]
    assert mine.noise_figures.N.unit == col["noise_figures"]["white"]["unit"] == "g/sqrt(Hz)"
    rw = mine.parameter("gamma2", "RW")
    assert (rw.value, rw.ci_low, rw.ci_high, rw.interval) == next(
        (p["value"], p["ci_low"], p["ci_high"], p["interval"]) for p in col["parameters"] if p["process"] == "RW")
    with pytest.raises(KeyError):
        mine.parameter("sigma2")  # AR1's and WN's: name the process
    # The CLI's column loads as the same typed result.
    assert gmwm.FitResult.from_json(cli_column_texts(text)[0]).to_json() == mine.to_json()


def test_select_equals_the_cli_json_bit_for_bit_on_two_columns_and_types_the_ranking(tmp_path, example):
    text = cli_text(tmp_path, "select", EXAMPLE, "--columns", "gyro_z,accel_x", "--model", "AR1+WN+RW",
                    "--units", "gyro=rad/s,accel=m/s^2")
    doc = json.loads(text)
    data = np.column_stack([example["gyro_z"], example["accel_x"]])
    mine = gmwm.select(data, "AR1+WN+RW", freq=doc["columns"][0]["freq"], names=["gyro_z", "accel_x"],
                       units="gyro=rad/s,accel=m/s^2")
    assert isinstance(mine, gmwm.SelectResult) and len(mine) == 2
    assert_text_is_the_document(mine, doc["columns"])
    assert mine.to_json() == member_text(text, "columns")
    for m, c, cli_col in zip(mine, doc["columns"], cli_column_texts(text), strict=True):
        assert c["noise_figures"] and c["best_kalman"]
        assert_text_is_the_document(m, c)
        assert m.to_json() == cli_col
        check_select_column(m, c)
    assert [m.unit for m in mine] == ["rad/s", "m/s^2"]
    assert mine[0].best_fit.noise_figures.K.unit == "rad/s^2/sqrt(Hz)"


def test_robust_fit_and_select_equal_the_cli_json_bit_for_bit(tmp_path, example):
    doc = cli_json(tmp_path, "fit", EXAMPLE, "--columns", "gyro_y", "--model", "AR1+WN+RW", "--robust", "--eff", "0.8")
    col = doc["columns"][0]
    mine = gmwm.fit(example["gyro_y"], "AR1+WN+RW", freq=col["freq"], name="gyro_y", robust=True, eff=0.8)
    assert_text_is_the_document(mine, col)
    check_fit_column(mine, col)
    assert mine.estimator == "huber" and mine.efficiency == 0.8
    doc = cli_json(tmp_path, "select", EXAMPLE, "--columns", "accel_z", "--model", "AR1+WN+RW", "--robust",
                   "--estimator", "bisquare")
    col = doc["columns"][0]
    mine = gmwm.select(example["accel_z"], "AR1+WN+RW", freq=col["freq"], names=["accel_z"], robust=True,
                       estimator="bisquare")[0]
    assert_text_is_the_document(mine, col)
    check_select_column(mine, col)
    with pytest.raises(gmwm.InputError, match="eff 0.6: only meaningful with robust=True"):
        gmwm.fit(example["gyro_y"], "WN", freq=100.0, eff=0.6)
    with pytest.raises(gmwm.InputError, match="estimator: found 'tukey', expected huber or bisquare"):
        gmwm.fit(example["gyro_y"], "WN", freq=100.0, robust=True, estimator="tukey")


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
    assert len(gmwm.select(mine, "WN+RW", freq=1.0)) == 2


def test_bad_input_raises_input_error_with_the_cli_message(tmp_path, example):
    with pytest.raises(gmwm.InputError) as e:
        gmwm.fit(example["gyro_x"], "AR1+FOO", freq=100.0)
    cli = subprocess.run([CLI, "fit", EXAMPLE, "--columns", "gyro_x", "--model", "AR1+FOO"], capture_output=True,
                         text=True)
    assert cli.returncode == 2
    assert str(e.value) in cli.stderr
    assert isinstance(e.value, ValueError)
    # NaN marks a missing sample (test_gaps.py); an infinity is refused.
    with pytest.raises(gmwm.InputError, match="sample 2 is not a finite number"):
        gmwm.wv(np.array([1.0, 2.0, np.inf] + [0.0] * 100))
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


def test_an_array_without_freq_is_refused_as_a_file_without_timestamps(tmp_path, example):
    """One rule (issue 45): the command line refuses a file without a timestamp column and no
    --freq; an array carries no timing either, and Python took a missing freq silently (its
    result had no figure in seconds and said nothing)."""
    no_time = tmp_path / "no_time.csv"
    no_time.write_text("gyro_x\n" + "\n".join(repr(v) for v in example["gyro_x"][:4096]) + "\n")
    cli = subprocess.run([CLI, "fit", str(no_time), "--model", "WN"], capture_output=True, text=True)
    assert cli.returncode == 2
    assert cli.stderr.strip().endswith("no timestamp column found; give the sampling rate with --freq HZ")
    x = example["gyro_x"]
    for call in (lambda: gmwm.wv(x), lambda: gmwm.fit(x, "WN"), lambda: gmwm.select(x, "WN+RW"),
                 lambda: gmwm.allan(x), lambda: gmwm.gap(x, model="WN(sigma2=1e-4)"),
                 lambda: gmwm.fit_joint([x, x * 1.1], "WN"), lambda: gmwm.select_joint([x, x * 1.1], "WN+RW")):
        with pytest.raises(gmwm.InputError) as e:
            call()
        assert str(e.value) == ("data: an array carries no timestamps (a Recording, or a pandas time index, "
                                "carries its rate); give the sampling rate with freq (Hz)")
    assert gmwm.fit(x, "WN", freq=1.0).freq == 1.0  # tau in samples, said so


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
    assert gmwm.fit(x, "WN+RW", freq=freq, units="deg/s").unit == "deg/s"
    assert gmwm.fit(x, "WN+RW", freq=freq, units="gyro=deg/s", name="gyro_x").unit == "deg/s"
    assert gmwm.fit(x, "WN+RW", freq=freq, units="accel=g", name="gyro_x").unit == "rad/s"


def test_a_constant_or_underflowing_series_is_refused_naming_it(example):
    # Issue 25: these came back "converged" at a parameter floor of 3.7e-44.
    with pytest.raises(gmwm.InputError, match="found all 1000 values equal to 1.5, expected a varying signal"):
        gmwm.fit(np.full(1000, 1.5), "WN")
    with pytest.raises(gmwm.InputError, match="found all 1000 values equal to 0"):
        gmwm.select(np.zeros(1000), "WN+RW")
    tiny = example["gyro_x"] * 1e-300
    for call in (lambda: gmwm.wv(tiny, freq=100.0, name="gyro_x"),
                 lambda: gmwm.fit(tiny, "WN+RW", freq=100.0, name="gyro_x"),
                 lambda: gmwm.allan(tiny, freq=100.0)):
        with pytest.raises(gmwm.InputError, match="zero at every level although the values vary"):
            call()
    with pytest.raises(gmwm.InputError, match="column 'gyro_x': the wavelet variance at level"):
        gmwm.fit(example["gyro_x"] * 1e160, "WN+RW", freq=100.0, name="gyro_x")


def test_computations_release_the_gil(example):
    # Two selections in threads finish with the same results as one after the other; while
    # they run, the interpreter keeps executing Python (a counter advances).
    data = example["gyro_x"]
    expected = gmwm.select(data, "2*AR1+WN+RW", freq=100.0).to_json()
    results, ticks, done = [], [0], threading.Event()

    def work():
        results.append(gmwm.select(data, "2*AR1+WN+RW", freq=100.0).to_json())

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


def test_nav_equals_the_cli_json_bit_for_bit_and_types_each_filter(tmp_path):
    sel = tmp_path / "sel.json"
    subprocess.run([CLI, "select", EXAMPLE, "--model", "AR1+WN+RW", "--units", "gyro=rad/s,accel=m/s^2", "--json",
                    str(sel), "--quiet"], check=True)
    kalibr = os.path.join(SOURCE, "data", "adis16405_imu.yaml")
    doc = cli_json(tmp_path, "nav", "--truth", str(sel), "--filter", "truth", "--filter", "wnrw*2", "--filter", kalibr,
                   "--outage", "120:180", "--horizon", "240", "--monte-carlo", "20")
    doc.pop("run")
    mine = gmwm.nav(str(sel), ["truth", "wnrw*2", kalibr], outages=[(120.0, 180.0)], horizon=240.0, monte_carlo=20)
    assert isinstance(mine, gmwm.NavResult)
    assert_text_is_the_document(mine, doc)
    assert mine.filters[0].verdict == "consistent"
    assert mine.scenario.outages == ((120.0, 180.0),) and mine.scenario.horizon == 240.0
    assert mine.truth_source == doc["truth"]["source"] and list(mine.truth_models) == doc["truth"]["models"]
    assert mine.units == doc["units"] and mine.monte_carlo == doc["monte_carlo"]
    for typed, f in zip(mine.filters, doc["filters"], strict=True):
        assert_fields(typed, f, ("label", "source", "verdict", "nees_inside", "nees_above"))
        assert typed.nees_band == tuple(f["nees_band"])
        for key in f["curves"]:
            assert_floats(getattr(typed.curves, key), f["curves"][key], key)
        assert_fields(typed.summary, f["summary"], list(f["summary"]))
        assert typed.monte_carlo.verdict == f["monte_carlo"]["verdict"]
        assert_floats(typed.monte_carlo.nees, f["monte_carlo"]["nees"], "monte_carlo.nees")
    assert mine.filter("truth") is mine.filters[0]


def test_nav_refuses_a_bad_trajectory_and_source_with_the_clis_message(tmp_path):
    with pytest.raises(gmwm.InputError, match="^trajectory: found 'maneuver', expected static, constant-velocity or manoeuvre$"):
        gmwm.nav("gyro=WN(sigma2=1e-6);accel=WN(sigma2=1e-4)", trajectory="maneuver", rate=100.0)
    with pytest.raises(gmwm.InputError, match=r"the inflation after '\*' must be a positive number"):
        gmwm.nav("gyro=WN(sigma2=1e-6);accel=WN(sigma2=1e-4)", ["truth*0"], rate=100.0)


def test_plan_equals_the_cli_json_bit_for_bit_and_types_the_targets(tmp_path):
    doc = cli_json(tmp_path, "plan", "--model", "WN(sigma2=1e-8)+RW(gamma2=1e-14)", "--freq", "100", "--unit", "rad/s",
                   "--targets", "N,K", "--have", "3600")
    doc.pop("run")
    mine = gmwm.plan(model="WN(sigma2=1e-8)+RW(gamma2=1e-14)", freq=100.0, unit="rad/s", targets=["N", "K"], have=3600.0)
    assert isinstance(mine, gmwm.PlanResult)
    assert_text_is_the_document(mine, doc)
    assert_fields(mine, doc, ("source", "precision", "confidence", "record_seconds"))
    for typed, c in zip(mine.columns, doc["columns"], strict=True):
        assert_fields(typed, c, ("name", "unit", "model", "freq"))
        assert (typed.resolved.samples, typed.resolved.seconds, typed.resolved.by) == tuple(c["resolved"].values())
        for t, j in zip(typed.targets, c["targets"], strict=True):
            assert_fields(t, j, ("name", "value", "unit", "reachable", "samples", "seconds", "own_samples",
                                 "relative_se", "precision_at_record", "basis"))
    assert mine.columns[0].target("N").seconds == doc["columns"][0]["targets"][0]["seconds"]
    with pytest.raises(gmwm.InputError, match="has no random walk term"):
        gmwm.plan(model="WN(sigma2=1e-8)", freq=100.0, targets=["K"])


def test_plan_of_a_result_object_its_file_or_its_text_equals_gmwm_plan_of_the_file(tmp_path):
    # The notebook's step (issue 46, item 4): plan from the selection just made, as from its file.
    x = gmwm.simulate("AR1(phi=0.99,sigma2=1e-6)+WN(sigma2=1e-4)+RW(gamma2=1e-9)", 2**15, seed=11, freq=100)
    np.savetxt(tmp_path / "x.csv", x, header="gyro_x", comments="")
    sel = tmp_path / "select.json"
    subprocess.run([CLI, "select", str(tmp_path / "x.csv"), "--freq", "100", "--model", "AR1+WN+RW", "--units", "rad/s",
                    "--json", str(sel), "--quiet"], check=True)
    doc = cli_json(tmp_path, "plan", str(sel), "--targets", "N,B")
    doc.pop("run")
    assert gmwm.plan(str(sel), targets=["N", "B"]).document == doc
    selection = gmwm.select(x, "AR1+WN+RW", freq=100, units="rad/s", names=["gyro_x"])
    for given in (selection, sel.read_text()):
        mine = gmwm.plan(given, targets=["N", "B"])
        assert mine.source == "gmwm select result"
        assert mine.document == {**doc, "source": "gmwm select result"}
    one = gmwm.plan(gmwm.fit(x, "AR1+WN+RW", freq=100, units="rad/s", name="gyro_x"), targets=["N"])
    assert one.source == "gmwm fit result" and one.columns[0].name == "gyro_x"
    assert one.columns[0].target("N").seconds > 0


def test_gap_check_equals_the_cli_json_bit_for_bit_and_refuses_as_it_does(tmp_path):
    args = ["--cases", "1", "--n", "4096", "--replicates", "40", "--families", "STEP,DR", "--strengths", "8",
            "--no-null"]
    doc = cli_json(tmp_path, "gap-check", *args)
    mine = gmwm.gap_check(cases=1, n=4096, replicates=40, families="STEP,DR", strengths="8", null=False)
    doc.pop("run", None)
    assert isinstance(mine, gmwm.GapCheckResult)
    assert_text_is_the_document(mine, doc)
    assert_fields(mine, doc, ("n", "replicates", "seed", "cases", "correct", "false_alarms"))
    assert_floats(mine.strengths, doc["strengths"], "strengths")
    assert mine.confusion == doc["confusion"]
    assert mine.power == {t: {float(s): v for s, v in row.items()} for t, row in doc["power"].items()}
    for name, fam in mine.families.items():
        assert_fields(fam, doc["families"][name], [f.name for f in dataclasses.fields(fam)])
    for case, j in zip(mine.case_list, doc["case_list"], strict=True):
        assert_fields(case, j, [f.name for f in dataclasses.fields(case)])
    bad = subprocess.run([CLI, "gap-check", "--families", "STEP,XX", "--quiet"], capture_output=True, text=True)
    assert bad.returncode == 2
    with pytest.raises(gmwm.InputError) as e:
        gmwm.gap_check(families="STEP,XX")
    assert str(e.value) in bad.stderr
    with pytest.raises(gmwm.InputError, match="--strengths 'inf'"):
        gmwm.gap_check(strengths="inf")


def test_every_result_is_frozen_with_read_only_arrays_and_a_one_line_repr(example):
    x = example["gyro_x"][:8192]
    results = [gmwm.wv(x, freq=100.0), gmwm.allan(x, freq=100.0, units="rad/s"),
               gmwm.fit(x, "AR1+WN+RW", freq=100.0, units="rad/s"), gmwm.select(x, "AR1+WN+RW", freq=100.0),
               gmwm.plan(model="WN(sigma2=1e-8)+RW(gamma2=1e-14)", freq=100.0, unit="rad/s")]
    results += [results[2].parameters[0], results[2].noise_figures, results[2].noise_figures.N, results[2].levels,
                results[2].allan, results[2].kalman, results[3][0], results[3][0].ranking[0], results[3][0].best_fit]
    for r in results:
        text = repr(r)
        assert "\n" not in text and len(text) < 200, text
    f = results[2]
    with pytest.raises(dataclasses.FrozenInstanceError):
        f.model = "WN"
    with pytest.raises(ValueError):
        f.implied_wv[0] = 0.0  # read-only: the document's numbers
    assert "AR1+WN+RW" in repr(f) and f.status in repr(f)


def test_the_functions_keep_their_signature_and_document_the_typed_return():
    signature = inspect.signature(gmwm.fit)
    assert list(signature.parameters)[:2] == ["data", "model"]
    assert signature.parameters["freq"].kind is inspect.Parameter.KEYWORD_ONLY
    assert signature.parameters["omega"].default == "model"
    assert signature.return_annotation == "gmwm.FitResult"
    assert gmwm.fit.__doc__.startswith("fit(data: object, model: str, *, freq: Optional[float] = None")
    assert "GMWM fit of a model" in gmwm.fit.__doc__ and "gmwm.FitResult" in gmwm.fit.__doc__
    # plan, like export, is written out in Python (it takes a result object): its own signature.
    assert list(inspect.signature(gmwm.plan).parameters)[:2] == ["result", "model"]
    assert inspect.signature(gmwm.plan).return_annotation in ("PlanResult", gmwm.PlanResult)
    for name in ("wv", "allan", "select", "gap", "gap_check", "nav"):
        function = getattr(gmwm, name)
        assert function.__name__ == name and function.__doc__.startswith(name + "(")
        assert inspect.signature(function).return_annotation.startswith("gmwm.")
