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
