"""Signals in (issue 45: input reading shared by every face): gmwm.read reads every format the
command reads, with the command's readers, limits and refusals (naming Python's keywords);
a Recording, or a pandas object with a time index, carries its rate and names into every
function, which then gives the command's JSON on the same data."""
import gzip
import json
import struct
import warnings

import numpy as np
import pytest

import gmwm
from cli_support import SOURCE, run

RATE = 200
STEP_NS = 1_000_000_000 // RATE
N = 4096


def imu_values(n):
    """The log writers' test signal (tests/support/log_writers.cc imu_values): gyro then accel."""
    i = np.arange(n, dtype=np.float64)
    return np.column_stack([np.sin(i * 0.1) * 1e-3, np.cos(i * 0.37) * 2e-3, (i % 11) * 1e-4,
                            9.81 + (i % 7) * 1e-3, np.sin(i * 0.05) * 0.02, -(i % 5) * 3e-3])


def write_csv(path, values, stamps_ns=None, names=("gyro_x", "gyro_y", "gyro_z")):
    stamps = np.arange(len(values), dtype=np.int64) * STEP_NS if stamps_ns is None else stamps_ns
    lines = ["timestamp [ns]," + ",".join(names)]
    lines += [f"{t}," + ",".join(repr(float(v)) for v in row) for t, row in zip(stamps, values)]
    opener = gzip.open if str(path).endswith(".gz") else open
    with opener(path, "wt") as f:
        f.write("\n".join(lines) + "\n")
    return path


def write_ulog(path, n=N):
    """A PX4 ULog of n sensor_combined messages at 200 Hz (the file format's header, 'F'
    format, 'A' subscription and 'D' data messages; PX4's sensor_combined layout)."""
    def message(kind, payload):
        return struct.pack("<HB", len(payload), ord(kind)) + payload

    out = b"ULog\x01\x12\x35\x01" + struct.pack("<Q", 1_000_000)
    out += message("F", b"sensor_combined:uint64_t timestamp;float[3] gyro_rad;uint32_t gyro_integral_dt;"
                        b"int32_t accelerometer_timestamp_relative;float[3] accelerometer_m_s2;"
                        b"uint32_t accelerometer_integral_dt;uint8_t accelerometer_clipping;uint8_t gyro_clipping;"
                        b"uint8_t accel_calibration_count;uint8_t gyro_calibration_count;")
    out += message("A", struct.pack("<BH", 0, 0) + b"sensor_combined")
    v = imu_values(n).astype(np.float32)
    for i in range(n):
        body = struct.pack("<Q", 1_000_000 + 5000 * i) + struct.pack("<3f", *v[i, :3]) + struct.pack("<Ii", 5000, 0)
        body += struct.pack("<3f", *v[i, 3:]) + struct.pack("<II", 5000, 0)
        out += message("D", struct.pack("<H", 0) + body)
    path.write_bytes(out)
    return path


def cli_json(tmp_path, *args):
    return json.loads(run(tmp_path, *args, "--json", "-").stdout)


@pytest.fixture(scope="module")
def csv_file(tmp_path_factory):
    x = gmwm.simulate("WN(sigma2=1e-4)+RW(gamma2=1e-9)", N, freq=RATE, signals=3, seed=11)
    return write_csv(tmp_path_factory.mktemp("read") / "imu.csv.gz", x)


def test_a_recording_has_the_columns_names_rate_and_timing_the_command_reads(csv_file):
    rec = gmwm.read(csv_file)
    assert rec.names == ("gyro_x", "gyro_y", "gyro_z")
    assert rec.values.shape == (N, 3) and not rec.values.flags.writeable
    assert rec.freq == pytest.approx(RATE, rel=1e-12)
    assert rec.timing.column == "timestamp [ns]" and rec.timing.unit == "ns" and rec.timing.gaps == 0
    assert len(rec) == N and rec["gyro_y"].names == ("gyro_y",)
    np.testing.assert_array_equal(rec.column("gyro_z"), rec.values[:, 2])
    assert "3 columns" in repr(rec) and "freq=200 Hz" in repr(rec)


def test_a_read_recording_fits_and_selects_exactly_as_the_command_on_the_file(csv_file, tmp_path):
    rec = gmwm.read(csv_file)
    f = gmwm.fit(rec["gyro_x"], "WN+RW")
    cli = cli_json(tmp_path, "fit", str(csv_file), "--columns", "gyro_x", "--model", "WN+RW")
    assert f.name == "gyro_x" and f.document == cli["columns"][0]
    s = gmwm.select(rec, "WN+RW")
    cli = cli_json(tmp_path, "select", str(csv_file), "--model", "WN+RW")
    assert [c.document for c in s] == cli["columns"]
    w = gmwm.wv(gmwm.read(csv_file, columns="gyro_y"))
    assert w.document == cli_json(tmp_path, "wv", str(csv_file), "--columns", "gyro_y")["columns"][0]


def test_columns_pick_by_name_or_one_based_index_and_freq_overrides_the_stamps(csv_file):
    by_index = gmwm.read(csv_file, columns=[4, 2])  # the file's fields, the timestamp being the first
    assert by_index.names == ("gyro_z", "gyro_x")
    assert gmwm.read(csv_file, columns="gyro_z, gyro_x").names == ("gyro_z", "gyro_x")
    with pytest.warns(gmwm.TimingWarning, match=r"imu.csv.gz: timestamps .* 200 Hz, 0 gaps, 0 out of order; freq "
                                                r"100 Hz disagrees with them by 100% \(freq is used\)$"):
        assert gmwm.read(csv_file, freq=100).freq == 100


@pytest.mark.parametrize("call,words", [
    (lambda p: gmwm.read(p, columns=["nope"]), "columns"),
    (lambda p: gmwm.read(p, columns="a,,b"), "columns 'a,,b': found an empty name"),
    (lambda p: gmwm.read(p, columns=[]), "columns: found an empty list"),
    (lambda p: gmwm.read(p, freq=0), "freq: found 0"),
    (lambda p: gmwm.read(p, memory=0.5), "memory: found '0.5', expected a number of MB from 1 to 1e12"),
    (lambda p: gmwm.read(p, topic="/imu"), "topic"),
    (lambda p: gmwm.fleet(p, model="WN", memory=0.5), "memory: found '0.5', expected a number of MB from 1 to 1e12"),
])
def test_a_bad_read_is_refused_in_one_line_naming_the_python_keyword(csv_file, call, words):
    with pytest.raises(gmwm.InputError) as e:
        call(csv_file)
    message = str(e.value)
    assert words in message and "--" not in message and "\n" not in message


def test_a_file_without_timestamps_needs_freq_in_pythons_words(tmp_path):
    path = tmp_path / "plain.csv"
    path.write_text("gyro_x\n" + "\n".join(repr(float(v)) for v in np.sin(np.arange(64) * 0.3)) + "\n")
    with pytest.raises(gmwm.InputError, match=r"plain.csv: no timestamp column found; give the sampling rate with "
                                              r"freq \(Hz\)$"):
        gmwm.read(path)
    assert gmwm.read(path, freq=50).freq == 50


def test_the_same_refusal_reaches_the_command_line_in_its_words(tmp_path):
    path = tmp_path / "plain.csv"
    path.write_text("gyro_x\n" + "\n".join(repr(float(v)) for v in np.sin(np.arange(64) * 0.3)) + "\n")
    done = run(tmp_path, "wv", str(path), check=False)
    assert done.returncode == 2
    with pytest.raises(gmwm.InputError) as e:
        gmwm.read(path)
    assert done.stderr.strip().endswith(str(e.value).replace("freq (Hz)", "--freq HZ"))


def test_a_record_beyond_its_memory_is_refused_since_python_takes_the_values_in_memory(tmp_path):
    big = write_csv(tmp_path / "big.csv", imu_values(120_000)[:, :3], np.arange(120_000, dtype=np.int64) * STEP_NS)
    with pytest.raises(gmwm.InputError, match=r"expected at most .*memory"):
        gmwm.read(big, memory=1)


def test_every_log_format_gives_the_values_and_rate_the_command_reads(tmp_path):
    # Bags written by ROS's own Python writer (rosbag) and by the rosbag2 schema, as their tests do.
    from test_rosbag1 import write_bag as write_rosbag1
    from test_rosbag2 import write_bag as write_rosbag2

    ulog = write_ulog(tmp_path / "flight.ulg")
    mcap = f"{SOURCE}/tests/data/mcap/imu_zstd.mcap"
    write_rosbag1(str(tmp_path / "ros1.bag"), compression="bz2")
    write_rosbag2(str(tmp_path / "ros2.db3"))
    for path, topic in ((ulog, None), (mcap, None), (tmp_path / "ros1.bag", "/imu/data"),
                        (tmp_path / "ros2.db3", None)):
        rec = gmwm.read(path, topic=topic)
        cli = cli_json(tmp_path, "wv", str(path), *(["--topic", topic] if topic else []))
        assert list(rec.names) == [c["name"] for c in cli["columns"]]
        assert rec.freq == pytest.approx(cli["columns"][0]["freq"], rel=1e-12)
        w = gmwm.wv(rec[0])
        assert w.document == cli["columns"][0]
    rec = gmwm.read(ulog, columns=["gyro_x"])
    np.testing.assert_array_equal(rec.values[:, 0], imu_values(N)[:, 0].astype(np.float32).astype(np.float64))


def test_a_recording_of_several_columns_is_refused_by_a_one_series_function(csv_file):
    rec = gmwm.read(csv_file)
    with pytest.raises(gmwm.InputError, match=r"data: found a recording of 3 columns, expected one series "
                                              r"\(e.g. data\['gyro_x'\]\)"):
        gmwm.fit(rec, "WN+RW")


def test_replicates_take_recordings_and_their_common_rate(csv_file, tmp_path):
    rec = gmwm.read(csv_file)
    other = gmwm.read(write_csv(tmp_path / "other.csv", rec.values[::-1].copy()))
    j = gmwm.fit_joint([rec, other], "WN+RW", test_draws=19)
    assert [c.name for c in j.columns] == ["gyro_x", "gyro_y", "gyro_z"]
    assert j.to_json() == gmwm.fit_joint([rec.values, other.values], "WN+RW", test_draws=19, freq=RATE,
                                         names=list(rec.names)).to_json()
    slow = write_csv(tmp_path / "slow.csv", rec.values, np.arange(N, dtype=np.int64) * 2 * STEP_NS)
    with pytest.raises(gmwm.InputError, match=r"replicates\[1\]: sampled at 100 Hz, replicates\[0\] at 200 Hz"):
        gmwm.fit_joint([rec, gmwm.read(slow)], "WN+RW")


pd = pytest.importorskip("pandas")


def test_a_series_with_a_datetime_index_carries_its_rate_and_name(csv_file, tmp_path):
    rec = gmwm.read(csv_file)
    index = pd.to_datetime(np.arange(N, dtype=np.int64) * STEP_NS + 1_700_000_000_000_000_000, unit="ns")
    series = pd.Series(rec.column("gyro_x"), index=index, name="gyro_x")
    f = gmwm.fit(series, "WN+RW")
    assert f.freq == pytest.approx(RATE, rel=1e-12) and f.name == "gyro_x"
    assert f.document == gmwm.fit(rec["gyro_x"], "WN+RW").document
    frame = pd.DataFrame(rec.values, columns=list(rec.names), index=pd.to_timedelta(index - index[0]))
    assert gmwm.select(frame, "WN+RW").to_json() == gmwm.select(rec, "WN+RW").to_json()


def test_an_index_with_gaps_warns_and_one_that_changes_rate_is_refused_as_a_files_stamps(tmp_path):
    x = gmwm.simulate("WN(sigma2=1e-4)", N, freq=RATE, seed=5)
    stamps = np.arange(N, dtype=np.int64) * STEP_NS
    gapped = stamps.copy()
    gapped[2000:] += 10 * STEP_NS
    with pytest.warns(gmwm.TimingWarning, match=r"data.index: timestamps 'index' in ns .*1 gap"):
        gmwm.wv(pd.Series(x, index=pd.to_timedelta(gapped, unit="ns")))
    changing = np.concatenate([stamps[:N // 2], stamps[N // 2 - 1] + np.arange(1, N - N // 2 + 1) * 2 * STEP_NS])
    with pytest.raises(gmwm.InputError) as e:
        gmwm.wv(pd.Series(x, index=pd.to_timedelta(changing, unit="ns")))
    message = str(e.value)
    assert message.startswith("data.index: timestamps 'index': the sampling rate changes within the record")
    assert "give freq (Hz) to take the samples as evenly spaced" in message
    cli = run(tmp_path, "wv", str(write_csv(tmp_path / "changing.csv", np.column_stack([x]), changing,
                                            names=("gyro_x",))), check=False)
    assert cli.returncode == 2
    assert message.split("timestamps ", 1)[1].split(":", 1)[1].replace("freq (Hz)", "--freq HZ") in cli.stderr
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gmwm.TimingWarning)  # freq takes the samples as evenly spaced
        assert gmwm.wv(pd.Series(x, index=pd.to_timedelta(changing, unit="ns")), freq=RATE).freq == RATE


def test_a_table_whose_stamp_columns_each_stamp_their_own_is_read_as_parts_as_the_command_reads_it(tmp_path):
    """Issue 47, item 3: gyro_timestamp,gyro_x,accel_timestamp,accel_x with each sensor's rows
    leaving the other's cells empty: gmwm.read_parts gives each stamp column's columns at the
    rate of its own stamps, the values the command's; gmwm.read refuses both at once and reads
    one part's columns at their own rate."""
    rng = np.random.default_rng(47)
    t0 = 1_700_000_000 * 10**9
    gyro = [(t0 + i * 2_500_000, rng.standard_normal() * 1e-3) for i in range(4000)]    # 400 Hz
    accel = [(t0 + i * 4_000_000, rng.standard_normal() * 2e-2) for i in range(2500)]   # 250 Hz
    rows = sorted([(t, 0, v) for t, v in gyro] + [(t, 1, v) for t, v in accel])
    lines = ["gyro_timestamp [ns],gyro_x,accel_timestamp [ns],accel_x"]
    lines += [f"{t},{v!r},," if s == 0 else f",,{t},{v!r}" for t, s, v in rows]
    path = tmp_path / "mixed.csv"
    path.write_text("\n".join(lines) + "\n")
    g, a = gmwm.read_parts(path)
    assert (g.names, len(g), g.topic) == (("gyro_x",), 4000, None)
    assert (a.names, len(a)) == (("accel_x",), 2500)
    assert g.freq == pytest.approx(400.0, rel=1e-9) and a.freq == pytest.approx(250.0, rel=1e-9)
    np.testing.assert_array_equal(a.column("accel_x"), [v for _, v in accel])
    with pytest.raises(gmwm.InputError, match="found 2 timestamp columns, each stamping the columns to its right"):
        gmwm.read(path)
    assert gmwm.read(path, columns="accel_x").freq == pytest.approx(250.0, rel=1e-9)
    doc = json.loads(run(tmp_path, "wv", str(path), "--json", "-").stdout)
    assert [p["stamps"] for p in doc["parts"]] == ["gyro_timestamp [ns]", "accel_timestamp [ns]"]
    np.testing.assert_allclose(gmwm.wv(a["accel_x"]).wv, [lv["wv"] for lv in doc["columns"][1]["levels"]],
                               rtol=1e-12)
