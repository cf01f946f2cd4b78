"""ROS 1 bag input of the gmwm command: bags written by ROS's own Python writer (Debian
python3-rosbag + python3-sensor-msgs, independent of the C++ reader), uncompressed, bz2 and
lz4, read with --topic; and the bad-bag paths (exit 2, one line, nothing written)."""
import json
import os
import struct
import subprocess

import numpy as np
import pytest

# Debian python3-rosbag and python3-sensor-msgs (tools/setup.sh installs them).
import rosbag
from genpy import Time
from sensor_msgs.msg import Imu, Temperature

SOURCE = os.environ.get("GMWM_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
CLI = os.path.abspath(os.environ.get("GMWM_CLI_PATH", os.path.join(SOURCE, "build", "gmwm")))
RATE = 200
STEP_NS = 1_000_000_000 // RATE


def values(n):
    i = np.arange(n)
    gyro = np.column_stack([np.sin(i * 0.1) * 1e-3, np.cos(i * 0.37) * 2e-3, (i % 11) * 1e-4])
    accel = np.column_stack([9.81 + (i % 7) * 1e-3, np.sin(i * 0.05) * 0.02, -(i % 5) * 3e-3])
    return gyro, accel


def imu(i, gyro, accel, stamp_ns):
    m = Imu()
    m.header.seq = i
    m.header.stamp = Time(stamp_ns // 10**9, stamp_ns % 10**9)
    m.header.frame_id = "imu_link"
    m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z = (float(x) for x in gyro)
    m.linear_acceleration.x, m.linear_acceleration.y, m.linear_acceleration.z = (float(x) for x in accel)
    return m


def write_bag(path, n=4096, compression="none", topic="/imu/data", stamps=None, extra=(), chunk_threshold=None):
    """n IMU messages on `topic` (and a Temperature topic interleaved, which the reader must
    skip); `extra`: more (topic, message-maker) pairs written every 10th message."""
    gyro, accel = values(n)
    start = 1_700_000_000 * 10**9
    kwargs = {"compression": compression}
    if chunk_threshold:
        kwargs["chunk_threshold"] = chunk_threshold
    with rosbag.Bag(path, "w", **kwargs) as bag:
        for i in range(n):
            t = start + i * STEP_NS if stamps is None else stamps[i]
            m = imu(i, gyro[i], accel[i], t)
            bag.write(topic, m, m.header.stamp)
            if i % 10 == 0:
                temp = Temperature()
                temp.header.stamp = m.header.stamp
                temp.temperature = 20.0 + i * 1e-3
                bag.write("/imu/temperature", temp, m.header.stamp)
                for name, make in extra:
                    bag.write(name, make(i, t), m.header.stamp)
    return gyro, accel


def run(tmp_path, *args):
    return subprocess.run([CLI, *args], capture_output=True, text=True, cwd=tmp_path)


def write_csv(path, gyro, accel):
    with open(path, "w") as f:
        f.write("gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z\n")
        for g, a in zip(gyro, accel):
            f.write(",".join(repr(float(x)) for x in (*g, *a)) + "\n")


@pytest.mark.parametrize("compression", ["none", "bz2", "lz4"])
def test_a_bag_gives_the_same_wv_as_the_same_values_in_csv_to_the_last_bit(tmp_path, compression):
    # A small chunk threshold: many chunks, read in parallel, must come back in order.
    gyro, accel = write_bag(str(tmp_path / "bag.bag"), compression=compression, chunk_threshold=64 * 1024)
    r = run(tmp_path, "wv", "bag.bag", "--topic", "/imu/data", "--json", "bag.json", "--quiet")
    assert r.returncode == 0, r.stderr
    write_csv(tmp_path / "same.csv", gyro, accel)
    r = run(tmp_path, "wv", "same.csv", "--freq", str(RATE), "--json", "csv.json", "--quiet")
    assert r.returncode == 0, r.stderr
    bag = json.loads((tmp_path / "bag.json").read_text())
    csv = json.loads((tmp_path / "csv.json").read_text())
    assert [c["name"] for c in bag["columns"]] == ["gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"]
    for b, c in zip(bag["columns"], csv["columns"]):
        assert b["n"] == 4096
        assert b["levels"] == c["levels"]
    assert bag["columns"][0]["freq"] == float(RATE)  # from the header stamps


def test_the_only_imu_topic_needs_no_name_and_columns_pick_axes(tmp_path):
    write_bag(str(tmp_path / "bag.bag"), compression="lz4")
    r = run(tmp_path, "wv", "bag.bag", "--columns", "gyro_z,accel_x", "--json", "o.json", "--quiet")
    assert r.returncode == 0, r.stderr
    assert [c["name"] for c in json.loads((tmp_path / "o.json").read_text())["columns"]] == ["gyro_z", "accel_x"]


def second_imu(i, t):
    return imu(i, (1e-3, 2e-3, 3e-3), (0.0, 0.0, 9.8), t)


def set_index_pos_to_zero(path):
    """An unindexed bag (an interrupted recording): the bag header's index_pos field zeroed."""
    data = bytearray(open(path, "rb").read())
    at = data.index(b"index_pos=") + len("index_pos=")
    data[at:at + 8] = struct.pack("<Q", 0)
    open(path, "wb").write(bytes(data))


def damage_first_chunk(path):
    """Bytes in the middle of the first bz2 chunk's data overwritten."""
    data = bytearray(open(path, "rb").read())
    at = data.index(b"BZh") + 200
    data[at:at + 64] = b"\x55" * 64
    open(path, "wb").write(bytes(data))


@pytest.mark.parametrize("case, args, words", [
    ("absent", ["--topic", "/nothere"], ["bag.bag: no topic /nothere in this bag (it has /imu/data (sensor_msgs/Imu), "
                                         "/imu/temperature (sensor_msgs/Temperature))"]),
    ("not imu", ["--topic", "/imu/temperature"], ["bag.bag: topic /imu/temperature is sensor_msgs/Temperature, "
                                                  "expected sensor_msgs/Imu messages"]),
    ("two imu topics", [], ["bag.bag: several sensor_msgs/Imu topics (/imu/data, /imu2): name one with --topic"]),
    ("unsorted", [], ["bag.bag: topic /imu/data message 12: header stamp 1700000000.050000000 s",
                      "unsorted stamps"]),
    ("truncated", [], ["bag.bag: ", "truncated"]),
    ("unindexed", [], ["bag.bag: the bag has no index", "rosbag reindex"]),
    ("version 1.2", [], ["bag.bag: found a ROS bag of version '1.2', expected 2.0"]),
    ("damaged bz2", [], ["bag.bag: chunk at byte ", "bz2 data does not decompress"]),
    ("too short", [], ["bag.bag: topic /imu/data has 8 messages, expected at least 16"]),
])
def test_a_bad_bag_exits_two_with_one_line_naming_file_topic_and_message(tmp_path, case, args, words):
    bag = str(tmp_path / "bag.bag")
    if case == "two imu topics":
        write_bag(bag, extra=(("/imu2", second_imu),))
    elif case == "unsorted":
        stamps = [1_700_000_000 * 10**9 + i * STEP_NS for i in range(4096)]
        stamps[10], stamps[11] = stamps[11], stamps[10]
        write_bag(bag, stamps=stamps)
    elif case == "damaged bz2":
        write_bag(bag, compression="bz2")
        damage_first_chunk(bag)
    elif case == "too short":
        write_bag(bag, n=8)
    else:
        write_bag(bag)
    if case == "truncated":
        size = os.path.getsize(bag)
        with open(bag, "r+b") as f:
            f.truncate(size // 2)
    elif case == "unindexed":
        set_index_pos_to_zero(bag)
    elif case == "version 1.2":
        with open(bag, "r+b") as f:
            f.write(b"#ROSBAG V1.2\n")
    r = run(tmp_path, "wv", "bag.bag", *args, "--json", "x.json")
    assert r.returncode == 2, r.stderr
    assert r.stderr.count("\n") == 1, r.stderr
    for w in words:
        assert w in r.stderr, r.stderr
    assert not (tmp_path / "x.json").exists()


def test_a_gyroscope_only_topic_leaves_out_the_axes_it_does_not_carry_in_python_as_on_the_command_line(tmp_path):
    """RealSense's /camera/gyro/sample carries linear_acceleration 0 in every message: gmwm.read
    gives the three gyroscope axes and a warning saying what it left out, as the command does."""
    import warnings

    import gmwm

    n = 1024
    gyro, _ = values(n)
    path = str(tmp_path / "gyro.bag")
    with rosbag.Bag(path, "w") as bag:
        for i in range(n):
            m = imu(i, gyro[i], (0.0, 0.0, 0.0), 1_700_000_000 * 10**9 + i * STEP_NS)
            bag.write("/camera/gyro/sample", m, m.header.stamp)
    said = f"accel_x, accel_y, accel_z are 0 in every one of its {n} messages (a sensor the topic does not carry): left out"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        rec = gmwm.read(path)
    assert rec.names == ("gyro_x", "gyro_y", "gyro_z")
    assert any(said in str(w.message) for w in caught), [str(w.message) for w in caught]
    r = subprocess.run([CLI, "wv", path, "--json", "-"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert said in " ".join(r.stderr.split())
    assert [c["name"] for c in json.loads(r.stdout)["columns"]] == list(rec.names)


def test_two_topics_at_different_rates_are_read_as_parts_in_python_as_on_the_command_line(tmp_path):
    """Issue 47, item 3: a RealSense-like bag, the gyroscope at 400 Hz and the accelerometer at
    250 Hz on topics of their own: gmwm.read_parts gives one Recording per topic at its own
    rate, and their WVs are the columns `gmwm wv --topic A,B` gives in one run."""
    import warnings

    import gmwm

    rng = np.random.default_rng(47)
    topics = {"/camera/gyro/sample": (400, 4000), "/camera/accel/sample": (250, 2500)}
    path = str(tmp_path / "d435i.bag")
    with rosbag.Bag(path, "w") as bag:
        for topic, (rate, n) in topics.items():
            x = rng.standard_normal((n, 3)) * 1e-3
            for i in range(n):
                triplet = tuple(float(v) for v in x[i])
                gyro, accel = (triplet, (0.0, 0.0, 0.0)) if "gyro" in topic else ((0.0, 0.0, 0.0), triplet)
                m = imu(i, gyro, accel, 1_700_000_000 * 10**9 + i * (10**9 // rate))
                bag.write(topic, m, m.header.stamp)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # each topic's left-out triplet, said as gmwm.read says it
        gyro, accel = gmwm.read_parts(path, topic=list(topics))
    assert (gyro.topic, gyro.names, len(gyro)) == ("/camera/gyro/sample", ("gyro_x", "gyro_y", "gyro_z"), 4000)
    assert (accel.topic, accel.names, len(accel)) == ("/camera/accel/sample", ("accel_x", "accel_y", "accel_z"), 2500)
    assert gyro.freq == pytest.approx(400.0, rel=1e-9) and accel.freq == pytest.approx(250.0, rel=1e-9)
    r = subprocess.run([CLI, "wv", path, "--topic", ",".join(topics), "--json", "-"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    doc = json.loads(r.stdout)
    assert [p["topic"] for p in doc["parts"]] == list(topics)
    columns = {c["name"]: c for c in doc["columns"]}
    for part in (gyro, accel):
        for name in part.names:
            col = gmwm.wv(part[name])
            assert columns[name]["freq"] == pytest.approx(part.freq, rel=1e-12)
            np.testing.assert_allclose(col.wv, [level["wv"] for level in columns[name]["levels"]], rtol=1e-12)
    with pytest.raises(gmwm.InputError,
                       match=r"found several topics where one record is read; wv, fit and select \(gmwm.read_parts\)"):
        gmwm.read(path, topic=",".join(topics))
    with pytest.raises(gmwm.InputError, match="columns mag_x: found in none of the parts"):
        gmwm.read_parts(path, topic=list(topics), columns=["mag_x"])
