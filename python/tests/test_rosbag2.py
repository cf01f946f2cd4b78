"""rosbag2 (sqlite3) input of the gmwm command: bags written here with Python's own sqlite3
and CDR packed by hand from the published layouts (independent of the C++ reader), read
with --topic, and their bad-file paths (exit 2, one line, nothing written)."""
import json
import os
import sqlite3
import struct
import subprocess

import numpy as np
import pytest

SOURCE = os.environ.get("GMWM_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
CLI = os.path.abspath(os.environ.get("GMWM_CLI_PATH", os.path.join(SOURCE, "build", "gmwm")))

# rosbag2's sqlite3 schema (rosbag2_storage_default_plugins).
SCHEMA = """
CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);
CREATE TABLE metadata(id INTEGER PRIMARY KEY, metadata_version INTEGER NOT NULL, metadata TEXT NOT NULL);
CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,
                    serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);
CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL, data BLOB NOT NULL);
"""


def imu_cdr(sec, nanosec, gyro, accel, frame="imu_link"):
    """sensor_msgs/msg/Imu in little-endian CDR: encapsulation 00 01 00 00, then the fields,
    each primitive aligned to its size from the end of the encapsulation header."""
    body = bytearray(struct.pack("<iI", sec, nanosec))
    name = frame.encode() + b"\0"
    body += struct.pack("<I", len(name)) + name
    body += b"\0" * ((-len(body)) % 8)  # align the doubles to 8
    doubles = [0.0, 0.0, 0.0, 1.0] + [0.0] * 9 + list(gyro) + [0.0] * 9 + list(accel) + [0.0] * 9
    body += struct.pack("<37d", *doubles)
    return b"\x00\x01\x00\x00" + bytes(body)


def values(n):
    i = np.arange(n)
    gyro = np.column_stack([np.sin(i * 0.1) * 1e-3, np.cos(i * 0.37) * 2e-3, (i % 11) * 1e-4])
    accel = np.column_stack([9.81 + (i % 7) * 1e-3, np.sin(i * 0.05) * 0.02, -(i % 5) * 3e-3])
    return gyro, accel


def write_bag(path, n=4096, rate=200, topics=(("/imu/data", "sensor_msgs/msg/Imu"),), stamps=None, data=None):
    db = sqlite3.connect(path)
    db.executescript(SCHEMA)
    for k, (name, typ) in enumerate(topics, start=1):
        db.execute("INSERT INTO topics VALUES (?, ?, ?, 'cdr', '')", (k, name, typ))
    gyro, accel = values(n)
    step = 1_000_000_000 // rate
    rows = []
    for i in range(n):
        t = 1_700_000_000 * 1_000_000_000 + i * step if stamps is None else stamps[i]
        blob = imu_cdr(t // 1_000_000_000, t % 1_000_000_000, gyro[i], accel[i]) if data is None else data(i)
        received = 1_700_000_000 * 1_000_000_000 + i * step + 12345  # the storage order: receive times
        rows.append((i + 1, 1, received, blob))
    db.executemany("INSERT INTO messages VALUES (?, ?, ?, ?)", rows)
    db.commit()
    db.close()
    return gyro, accel


def run(tmp_path, *args):
    return subprocess.run([CLI, *args], capture_output=True, text=True, cwd=tmp_path)


def test_a_bag_gives_the_same_wv_as_the_same_values_in_csv_to_the_last_bit(tmp_path):
    gyro, accel = write_bag(str(tmp_path / "bag.db3"))
    r = run(tmp_path, "wv", "bag.db3", "--topic", "/imu/data", "--json", "bag.json", "--quiet")
    assert r.returncode == 0, r.stderr
    with open(tmp_path / "same.csv", "w") as f:
        f.write("gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z\n")
        for g, a in zip(gyro, accel):
            f.write(",".join(repr(float(x)) for x in (*g, *a)) + "\n")
    r = run(tmp_path, "wv", "same.csv", "--freq", "200", "--json", "csv.json", "--quiet")
    assert r.returncode == 0, r.stderr
    bag = json.loads((tmp_path / "bag.json").read_text())
    csv = json.loads((tmp_path / "csv.json").read_text())
    assert [c["name"] for c in bag["columns"]] == ["gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"]
    for b, c in zip(bag["columns"], csv["columns"]):
        assert b["levels"] == c["levels"]
    assert bag["columns"][0]["freq"] == 200.0  # from the header stamps


def test_the_only_imu_topic_needs_no_name_and_columns_pick_axes(tmp_path):
    write_bag(str(tmp_path / "bag.db3"), topics=(("/imu/data", "sensor_msgs/msg/Imu"),))
    r = run(tmp_path, "wv", "bag.db3", "--columns", "gyro_z", "--json", "o.json", "--quiet")
    assert r.returncode == 0, r.stderr
    assert [c["name"] for c in json.loads((tmp_path / "o.json").read_text())["columns"]] == ["gyro_z"]


@pytest.mark.parametrize("case, args, words", [
    ("absent", ["--topic", "/nothere"], ["bag.db3: no topic /nothere in this bag (it has /imu/data (sensor_msgs/msg/Imu)"]),
    ("not imu", ["--topic", "/odom"], ["topic /odom is nav_msgs/msg/Odometry, expected sensor_msgs/msg/Imu"]),
    ("truncated", [], ["topic /imu/data message 3: truncated"]),
    ("unsorted", [], ["message 12: header stamp 0.050000000 s", "not after the previous message's: unsorted stamps"]),
    ("big-endian", [], ["message 1: found CDR encapsulation 0 0, expected 0 1"]),
])
def test_a_bad_bag_exits_two_with_one_line_naming_file_topic_and_message(tmp_path, case, args, words):
    bag = str(tmp_path / "bag.db3")
    if case == "not imu":
        write_bag(bag, topics=(("/imu/data", "sensor_msgs/msg/Imu"), ("/odom", "nav_msgs/msg/Odometry")))
    elif case == "truncated":
        gyro, accel = values(4096)
        write_bag(bag, data=lambda i: imu_cdr(*divmod(i * 5_000_000, 10**9), gyro[i], accel[i])[: 60 if i == 2 else None])
    elif case == "unsorted":
        stamps = [i * 5_000_000 for i in range(4096)]
        stamps[10], stamps[11] = stamps[11], stamps[10]
        write_bag(bag, stamps=stamps)
    elif case == "big-endian":
        gyro, accel = values(4096)
        write_bag(bag, data=lambda i: b"\x00\x00" + imu_cdr(*divmod(i * 5_000_000, 10**9), gyro[i], accel[i])[2:])
    else:
        write_bag(bag)
    r = run(tmp_path, "wv", "bag.db3", *args, "--json", "x.json")
    assert r.returncode == 2, r.stderr
    assert r.stderr.count("\n") == 1, r.stderr
    for w in words:
        assert w in r.stderr, r.stderr
    assert not (tmp_path / "x.json").exists()
