"""Held and interpolated samples in Python (issue 47, item 2): gmwm.read says which columns
repeat (Recording.repeated_samples, typed from the same schema as the command's JSON, and a
RepeatedSamplesWarning each), a column picked keeps its own, and an array handed to a function
is read for them as a file is."""
import json
import warnings

import numpy as np
import pytest

import gmwm
from cli_support import run

RATE = 400
N = 1 << 14


@pytest.fixture(scope="module")
def realsense_csv(tmp_path_factory):
    """A 400 Hz gyroscope's stamps; accel_x copies a 200 Hz measurement, accel_y joins two
    with a straight line at a phase of 0.37 of a measurement."""
    gyro = gmwm.simulate("WN(sigma2=1e-6)", N, freq=RATE, seed=1)
    a = gmwm.simulate("WN(sigma2=4e-4)", N // 2 + 2, freq=RATE / 2, seed=2)
    b = gmwm.simulate("WN(sigma2=4e-4)", N // 2 + 2, freq=RATE / 2, seed=3)
    t = np.arange(N)
    u = t / 2 + 0.37
    k = np.floor(u).astype(int)
    joined = b[k] + (u - k) * (b[k + 1] - b[k])
    path = tmp_path_factory.mktemp("repeated") / "realsense.csv"
    lines = ["time [s],gyro_x,accel_x,accel_y"] + [
        f"{t[i] / RATE!r},{float(gyro[i])!r},{float(a[i // 2])!r},{float(joined[i])!r}" for i in range(N)]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_read_says_which_columns_repeat_with_a_warning_each(realsense_csv):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        rec = gmwm.read(realsense_csv)
    said = [str(w.message) for w in caught if issubclass(w.category, gmwm.RepeatedSamplesWarning)]
    assert len(said) == 2, said
    assert "accel_x: 50% of the samples copy the one before (held" in said[0]
    assert "accel_y: 100% of the samples are an exact linear combination of their neighbours" in said[1]
    held, joined = rec.repeated_samples
    assert isinstance(held, gmwm.RepeatedSamples)
    assert held.column == "accel_x" and held.held_share == pytest.approx(0.5, abs=1e-3)
    assert held.first_clean_tau_seconds == pytest.approx(32 / RATE)
    assert joined.column == "accel_y" and joined.period == 2 and joined.held_share == 0.0
    # A column picked keeps its own; the gyroscope has none.
    assert [r.column for r in rec["accel_y"].repeated_samples] == ["accel_y"]
    assert rec["gyro_x"].repeated_samples == ()


def test_the_typed_entries_are_the_commands_json(realsense_csv):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gmwm.RepeatedSamplesWarning)
        rec = gmwm.read(realsense_csv)
    doc = json.loads(run(realsense_csv.parent, "wv", str(realsense_csv), "--json", "-").stdout)
    typed = [gmwm.RepeatedSamples.from_dict(d) for d in doc["repeated_samples"]]
    assert tuple(typed) == rec.repeated_samples


def test_an_array_handed_to_a_function_is_read_for_them_too(realsense_csv):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gmwm.RepeatedSamplesWarning)
        rec = gmwm.read(realsense_csv)
    with pytest.warns(gmwm.RepeatedSamplesWarning, match=r"^data: x1: 50% of the samples copy the one before"):
        gmwm.wv(np.array(rec.column("accel_x")), freq=RATE)
    with warnings.catch_warnings():
        warnings.simplefilter("error", gmwm.RepeatedSamplesWarning)
        gmwm.wv(np.array(rec.column("gyro_x")), freq=RATE)  # nothing to say


def test_fit_with_first_level_auto_is_the_commands_fit_above_the_smoothed_scales(realsense_csv):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gmwm.RepeatedSamplesWarning)
        rec = gmwm.read(realsense_csv)
        every = gmwm.fit(rec["accel_x"], "WN+RW")
        above = gmwm.fit(rec["accel_x"], "WN+RW", first_level="auto")
    assert every.first_level == 1 and every.gof.p_value < 0.05
    assert above.first_level >= 5 and above.gof.p_value > 0.05
    assert above.notes[0].startswith(f"fitted from level {above.first_level} (tau = ")
    assert len(above.implied_wv) == len(above.levels)
    doc = json.loads(run(realsense_csv.parent, "fit", str(realsense_csv), "--columns", "accel_x", "--model", "WN+RW",
                         "--first-level", "auto", "--json", "-").stdout)
    col = doc["columns"][0]
    assert col["first_level"] == above.first_level
    assert col["gof"]["statistic"] == pytest.approx(above.gof.statistic, rel=1e-9)
    # A level given as a number, a numpy integer or its digits is the same fit.
    for given in (above.first_level, np.int64(above.first_level), str(above.first_level)):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", gmwm.RepeatedSamplesWarning)
            again = gmwm.fit(rec["accel_x"], "WN+RW", first_level=given)
        assert again.gof.statistic == pytest.approx(above.gof.statistic, rel=1e-12)


@pytest.mark.parametrize("bad, shown", [(0, "0"), (63, "63"), (True, "True"), ("x", "'x'"), (2.0, "2.0"),
                                        (None, "None")])
def test_fit_refuses_a_first_level_it_cannot_take_with_the_commands_words(bad, shown):
    x = gmwm.simulate("WN(sigma2=1)", 1 << 12, freq=100, seed=4)
    with pytest.raises(gmwm.InputError) as e:
        gmwm.fit(x, "WN", first_level=bad)
    assert str(e.value) == f"first_level: found {shown}, expected auto or a whole number from 1 to 62"


def test_select_with_first_level_auto_is_the_commands(realsense_csv):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gmwm.RepeatedSamplesWarning)
        rec = gmwm.read(realsense_csv)
        (col,) = gmwm.select(rec["accel_x"], "WN+RW", first_level="auto")
    doc = json.loads(run(realsense_csv.parent, "select", str(realsense_csv), "--columns", "accel_x", "--model",
                         "WN+RW", "--first-level", "auto", "--json", "-").stdout)
    assert col.first_level == doc["columns"][0]["first_level"] >= 5
    assert col.best == doc["columns"][0]["best"]
    with pytest.raises(gmwm.InputError, match="first_level: found 'x', expected auto"):
        gmwm.select(rec["accel_x"], "WN+RW", first_level="x")


def test_gap_compares_above_the_smoothed_scales_by_default_as_the_command_does(realsense_csv):
    truth = "WN(sigma2=8e-4)"  # the 200 Hz white noise at 400 Hz: its density kept
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gmwm.RepeatedSamplesWarning)
        rec = gmwm.read(realsense_csv)
        (above,) = gmwm.gap(rec["accel_x"], model=truth, replicates=60).columns
        (every,) = gmwm.gap(rec["accel_x"], model=truth, replicates=60, first_level=1).columns
    assert above.gap.first_level >= 5 and not above.gap.detected
    assert above.notes[0].startswith(f"compared from level {above.gap.first_level} (tau = ")
    assert len(above.gap.levels.tau) == len(every.gap.levels.tau) - above.gap.first_level + 1
    assert every.gap.first_level == 1 and every.gap.detected  # the copies' deficit at the finest scales
    doc = json.loads(run(realsense_csv.parent, "gap", str(realsense_csv), "--columns", "accel_x", "--model", truth,
                         "--replicates", "60", "--json", "-").stdout)
    col = doc["columns"][0]
    assert col["gap"]["first_level"] == above.gap.first_level
    assert col["gap"]["statistic"] == pytest.approx(above.gap.statistic, rel=1e-12)
    with pytest.raises(gmwm.InputError, match="first_level: found 0, expected auto"):
        gmwm.gap(rec["accel_x"], model=truth, first_level=0)
