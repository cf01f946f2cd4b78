"""Records with missing samples in Python (issue 47, item 1): gmwm.read puts a NaN row where
the timestamps show a sample missing, and every function reads NaN rows as missing (each scale
from the windows that hold none), so a Recording, a DataFrame with NaN rows and the command on
the file give the same document; gaps="join" joins the samples end to end as --gaps join."""
import json
import re
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


def test_each_level_and_allan_point_says_how_many_of_its_windows_miss_samples(gappy_csv):
    w = gmwm.wv(read(gappy_csv), adev=True)
    partial = w.levels.partial
    assert partial is not None and len(partial) == len(w.levels.coefficients)
    assert (partial >= 0).all() and (partial <= w.levels.coefficients).all()
    assert partial[0] == 0, "level 1 reads the windows without a missing sample"
    assert partial[-1] > 0, "the longest windows cross a gap: read missing some samples"
    assert w.allan.complete is not None and w.allan.partial is not None
    assert len(w.allan.complete) == len(w.allan.tau) == len(w.allan.partial)
    assert w.allan.partial[-1] > 0
    # A regular record has neither.
    plain = gmwm.wv(gmwm.simulate("WN(sigma2=1)", 4096, freq=RATE, seed=1), freq=RATE, adev=True)
    assert plain.levels.partial is None and plain.allan.complete is None and plain.allan.partial is None


def test_the_robust_wv_reads_the_windows_without_a_gap_as_the_command_does(gappy_csv, tmp_path):
    rec = read(gappy_csv)
    w = gmwm.wv(rec, robust=True)
    assert w.document["estimator"] == "huber"
    assert w.document == cli_json(tmp_path, "wv", str(gappy_csv), "--robust")["columns"][0]
    # The windows read are the classical WV's, and a plain array with the NaN rows reads them too.
    assert w.levels.coefficients.tolist() == gmwm.wv(rec).levels.coefficients.tolist()
    assert gmwm.wv(rec.values[:, 0], freq=RATE, robust=True).levels.wv.tolist() == w.levels.wv.tolist()


def test_gap_diagnosis_reads_the_windows_without_a_gap_as_the_command_does(gappy_csv, tmp_path):
    rec = read(gappy_csv)
    g = gmwm.gap(rec, model="WN(sigma2=1)+RW(gamma2=1e-4)", replicates=40)
    cli = cli_json(tmp_path, "gap", str(gappy_csv), "--model", "WN(sigma2=1)+RW(gamma2=1e-4)", "--replicates", "40")
    for key in ("baseline_source", "replicates", "seed", "cross_axis", "columns"):
        assert g.document[key] == cli[key], key
    notes = " ".join(g.columns[0].notes)
    assert f"the record misses {len(DROPPED)} samples in 3 gaps" in notes


def test_the_joint_fit_reads_each_replicate_through_its_own_nan_rows_as_the_command_does(gappy_csv, tmp_path):
    rec = read(gappy_csv)
    other = gmwm.simulate("WN(sigma2=1)+RW(gamma2=1e-4)", N, freq=RATE, seed=6)
    other[3000:3200] = np.nan  # another unit, other gaps
    j = gmwm.fit_joint([rec, other], "WN+RW", test_draws=19)
    reps = j.document["columns"][0]["replicates"]
    assert [(r["missing_samples"], r["gaps"]) for r in reps] == [(len(DROPPED), 3), (200, 1)]
    # The first replicate's own fit is the fit of its record alone (its windows without a gap).
    alone = gmwm.fit(rec, "WN+RW").document["parameters"]
    for own, one in zip(reps[0]["fit"]["parameters"], alone):
        assert own["value"] == pytest.approx(one["value"], rel=1e-6)
    # The command on the two files: the same joint model.
    keep = np.flatnonzero(~np.isnan(other))
    path = tmp_path / "other.csv"
    path.write_text("time [s],gyro_x\n" + "".join(f"{k / RATE!r},{float(other[k])!r}\n" for k in keep))
    cli = cli_json(tmp_path, "fit", str(gappy_csv), "--model", "WN+RW", "--joint", str(path), "--replicates", "19")
    assert [p["value"] for p in cli["columns"][0]["parameters"]] == pytest.approx(
        [p["value"] for p in j.document["columns"][0]["parameters"]], rel=1e-9)


def test_an_infinity_and_an_unknown_gap_handling_are_refused(gappy_csv):
    x = read(gappy_csv).values[:, 0].copy()
    x[7] = np.inf
    with pytest.raises(gmwm.InputError, match="sample 7 is not a finite number"):
        gmwm.wv(x, freq=RATE)
    with pytest.raises(gmwm.InputError, match=r"gaps: found 'fill', expected 'windows'"):
        gmwm.read(gappy_csv, gaps="fill")


def test_decimation_and_increments_are_read_as_the_command_reads_them(tmp_path):
    x = gmwm.simulate("WN(sigma2=1)", 4096, freq=RATE, seed=9)
    path = tmp_path / "wn.csv"
    path.write_text("time [s],gyro_x\n" + "".join(f"{k / RATE!r},{float(v)!r}\n" for k, v in enumerate(x)))
    rec = read(path, decimate=4)
    assert len(rec) == 1024 and rec.freq == pytest.approx(RATE / 4, rel=1e-9)
    np.testing.assert_allclose(rec.values[:3, 0], x[:12].reshape(3, 4).mean(axis=1), rtol=1e-12)
    assert rec.conditioning.startswith("decimated by 4 (the mean of each 4 samples) from 100 Hz to 25 Hz")
    assert gmwm.wv(rec).document == cli_json(tmp_path, "wv", str(path), "--decimate", "4")["columns"][0]
    none = read(path, decimate=4, decimate_filter="none")
    np.testing.assert_allclose(none.values[:3, 0], x[0:12:4], rtol=1e-12)
    inc = read(path, data="increment")
    np.testing.assert_allclose(inc.values[:, 0], x * RATE, rtol=1e-9)
    assert inc.conditioning.startswith("read as increments x 100 Hz")
    assert read(path).conditioning is None
    with pytest.raises(gmwm.InputError, match="^decimate_filter: found 'sinc'"):
        gmwm.read(path, decimate=2, decimate_filter="sinc")


@pytest.mark.parametrize("decimate, found", [(2**40, "1099511627776"), (0, "0"), (np.int64(-3), "-3"),
                                             (2.5, "2.5"), (True, "True"), ("4", "'4'")])
def test_a_decimation_python_cannot_fit_in_an_int_is_refused_with_its_own_digits(tmp_path, decimate, found):
    path = tmp_path / "x.csv"
    path.write_text("x\n" + "\n".join(str(v) for v in np.random.default_rng(1).standard_normal(64)) + "\n")
    with pytest.raises(gmwm.InputError, match=rf"^decimate: found {re.escape(found)}, expected a whole number from 1 "
                                              r"to 1048576$"):
        gmwm.read(path, freq=100, decimate=decimate)
    assert len(gmwm.read(path, freq=100, decimate=np.int32(2))) == 32


def test_a_time_index_with_gaps_gives_nan_rows_where_its_stamps_show_samples_missing(gappy_csv, tmp_path):
    """A Series or DataFrame whose DatetimeIndex skips samples is read as the file with the same
    stamps: the same WV (each scale from the complete windows) and the same select."""
    pandas = pytest.importorskip("pandas")
    rec = read(gappy_csv)
    keep = ~np.isnan(rec.values[:, 0])
    stamps = pandas.to_datetime(np.flatnonzero(keep) * (1_000_000_000 // RATE), unit="ns")
    series = pandas.Series(rec.values[keep, 0], index=stamps, name="gyro_x")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gmwm.TimingWarning)
        w = gmwm.wv(series)
        frame = pandas.DataFrame({"gyro_x": rec.values[keep, 0], "copy": rec.values[keep, 0]}, index=stamps)
        s = gmwm.select(frame, "WN+RW")
    # The file's stamps are decimals (a rate of 100.000000002 Hz): the same windows, the same WV.
    cli = cli_json(tmp_path, "wv", str(gappy_csv))["columns"][0]
    assert [v["coefficients"] for v in cli["levels"]] == w.levels.coefficients.tolist()
    assert [v["wv"] for v in cli["levels"]] == w.levels.wv.tolist()
    assert [c.name for c in s.columns] == ["gyro_x", "copy"]
    assert s.columns[0].levels.wv.tolist() == w.levels.wv.tolist()
    # A given freq takes the samples as evenly spaced: joined end to end, as --freq does.
    with pytest.warns(gmwm.TimingWarning, match="3 gaps"):
        joined = gmwm.wv(series, freq=RATE)
    assert joined.n == int(keep.sum())
