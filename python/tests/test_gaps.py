"""Records with missing samples in Python (issue 47, item 1): gmwm.read puts a NaN row where
the timestamps show a sample missing, and every function reads NaN rows as missing (each scale
from the windows that hold none), so a Recording, a DataFrame with NaN rows and the command on
the file give the same document; gaps="join" joins the samples end to end as --gaps join."""
import json
import warnings

import numpy as np
import pytest

import gmwm
from cli_support import run

RATE = 100
N = 8192
DROPPED = list(range(1000, 1040)) + [5000] + list(range(6000, 6100))


@pytest.fixture(scope="module")
def gappy_csv(tmp_path_factory):
    x = gmwm.simulate("WN(sigma2=1)+RW(gamma2=1e-4)", N, freq=RATE, seed=5)
    keep = np.setdiff1d(np.arange(N), DROPPED)
    path = tmp_path_factory.mktemp("gaps") / "gappy.csv"
    lines = ["time [s],gyro_x"] + [f"{k / RATE!r},{float(x[k])!r}" for k in keep]
    path.write_text("\n".join(lines) + "\n")
    return path


def cli_json(folder, *args):
    return json.loads(run(folder, *args, "--json", "-").stdout)


def read(path, **options):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gmwm.TimingWarning)
        return gmwm.read(path, **options)


def test_a_read_recording_holds_a_nan_row_for_each_missing_sample(gappy_csv):
    rec = read(gappy_csv)
    assert len(rec) == N
    assert np.flatnonzero(np.isnan(rec.values[:, 0])).tolist() == DROPPED
    assert rec.timing.missing_samples == len(DROPPED) and rec.timing.gap_handling == "windows"
    assert rec.timing.gaps_read_as_missing
    joined = read(gappy_csv, gaps="join")
    assert len(joined) == N - len(DROPPED) and not np.isnan(joined.values).any()
    assert joined.timing.gap_handling == "join" and not joined.timing.gaps_read_as_missing


def test_wv_and_fit_of_the_recording_and_of_a_frame_with_nan_rows_equal_the_command(gappy_csv, tmp_path):
    rec = read(gappy_csv)
    w = gmwm.wv(rec)
    cli = cli_json(tmp_path, "wv", str(gappy_csv))
    assert w.document == cli["columns"][0]
    f = gmwm.fit(rec, "WN+RW")
    assert f.document == cli_json(tmp_path, "fit", str(gappy_csv), "--model", "WN+RW")["columns"][0]
    # A plain array with the same NaN rows at the same rate: the same WV.
    assert gmwm.wv(rec.values[:, 0], freq=RATE, name="gyro_x").levels.wv.tolist() == w.levels.wv.tolist()
    pandas = pytest.importorskip("pandas")
    frame = pandas.DataFrame({"gyro_x": rec.values[:, 0]})
    assert gmwm.fit(frame, "WN+RW", freq=RATE).levels.wv.tolist() == f.levels.wv.tolist()


def test_an_infinity_is_refused_and_a_study_without_a_window_form_says_to_drop_the_nan_rows(gappy_csv):
    x = read(gappy_csv).values[:, 0].copy()
    with pytest.raises(gmwm.InputError, match="robust WV reads a regular record: drop the NaN rows"):
        gmwm.wv(x, freq=RATE, robust=True)
    x[7] = np.inf
    with pytest.raises(gmwm.InputError, match="sample 7 is not a finite number"):
        gmwm.wv(x, freq=RATE)
    with pytest.raises(gmwm.InputError, match=r"gaps: found 'fill', expected 'windows'"):
        gmwm.read(gappy_csv, gaps="fill")
