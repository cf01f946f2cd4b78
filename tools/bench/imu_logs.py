#!/usr/bin/env python3
"""Writers of large IMU logs for the memory benchmarks (tools/bench/log_memory.py): a PX4 ULog
(sensor_combined), a ROS 1 bag (format 2.0, sensor_msgs/Imu, uncompressed chunks of about
768 kB as rosbag writes them) and an MCAP file (sensor_msgs/msg/Imu in CDR, uncompressed
chunks of about 1 MB), each of n messages at 200 Hz, written from the published formats with
numpy in blocks (a few MB of memory whatever n), independent of gmwm's readers.

    /usr/bin/python3 tools/bench/imu_logs.py ulog|ros1|mcap N FILE

Message i: stamps 1700000000 s + i * 5 ms; gyro and accel Gaussian (seed 25) around 0 and
(0, 0, 9.81). Never commit the files: 2e7 messages are 1.1 GB of ULog, 7.2 GB of bag, 6.9 GB
of MCAP.
"""
import bz2
import struct
import subprocess
import sys
import zlib

import numpy as np

STEP_NS = 5_000_000
FIRST_SEC = 1_700_000_000


def values(rng, n):
    gyro = rng.standard_normal((n, 3)) * 1e-3
    accel = rng.standard_normal((n, 3)) * 1e-2 + np.array([0.0, 0.0, 9.81])
    return gyro, accel


def stamps(first, n):
    t = (np.arange(first, first + n, dtype=np.uint64)) * np.uint64(STEP_NS)
    return (np.uint64(FIRST_SEC) + t // np.uint64(10**9)).astype(np.uint32), (t % np.uint64(10**9)).astype(np.uint32)


# --- PX4 ULog ------------------------------------------------------------------------------------

ULOG_FORMAT = (b"sensor_combined:uint64_t timestamp;float[3] gyro_rad;uint32_t gyro_integral_dt;"
               b"int32_t accelerometer_timestamp_relative;float[3] accelerometer_m_s2;uint32_t accelerometer_integral_dt;"
               b"uint8_t accelerometer_clipping;uint8_t gyro_clipping;uint8_t accel_calibration_count;"
               b"uint8_t gyro_calibration_count;")
ULOG_DATA = np.dtype([("size", "<u2"), ("type", "u1"), ("id", "<u2"), ("ts", "<u8"), ("gyro", "<f4", 3),
                      ("gdt", "<u4"), ("arel", "<i4"), ("acc", "<f4", 3), ("adt", "<u4"), ("flags", "u1", 4)])


def ulog_message(kind, payload):
    return struct.pack("<HB", len(payload), ord(kind)) + payload


def write_ulog(path, n, block=200_000):
    rng = np.random.default_rng(25)
    with open(path, "wb") as f:
        f.write(b"ULog\x01\x12\x35\x01" + struct.pack("<Q", 1_000_000))
        f.write(ulog_message("F", ULOG_FORMAT))
        f.write(ulog_message("A", struct.pack("<BH", 0, 0) + b"sensor_combined"))
        for first in range(0, n, block):
            k = min(block, n - first)
            d = np.zeros(k, ULOG_DATA)
            d["size"] = ULOG_DATA.itemsize - 3
            d["type"] = ord("D")
            d["ts"] = 1_000_000 + np.arange(first, first + k, dtype=np.uint64) * 5000
            gyro, accel = values(rng, k)
            d["gyro"], d["acc"] = gyro, accel
            d["gdt"] = d["adt"] = 5000
            f.write(d.tobytes())


# --- ROS 1 bag -----------------------------------------------------------------------------------

IMU_MD5 = b"6a62c6daae103f4ff57a132d6f95cec2"
ROS1_MESSAGE = np.dtype([
    ("hl", "<u4"), ("l_op", "<u4"), ("op", "S3"), ("opv", "u1"), ("l_conn", "<u4"), ("conn", "S5"), ("connv", "<u4"),
    ("l_time", "<u4"), ("time", "S5"), ("tsec", "<u4"), ("tnsec", "<u4"), ("dl", "<u4"),
    ("seq", "<u4"), ("sec", "<u4"), ("nsec", "<u4"), ("flen", "<u4"), ("frame", "S3"), ("d", "<f8", 37)])


def field(name, value):
    f = name + b"=" + value
    return struct.pack("<I", len(f)) + f


def record(fields, data):
    header = b"".join(fields)
    return struct.pack("<I", len(header)) + header + struct.pack("<I", len(data)) + data


def imu_doubles(k, gyro, accel):
    d = np.zeros((k, 37))
    d[:, 3] = 1.0
    d[:, 13:16] = gyro
    d[:, 25:28] = accel
    return d


def compress(data, codec):
    """A chunk's records as stored: bz2 (Python's bz2), lz4 (an LZ4 frame, the lz4 program) or
    zstd (a zstd frame, the zstd program); '' or 'none': as they are."""
    if codec in ("", "none"):
        return data
    if codec == "bz2":
        return bz2.compress(data)
    tool = {"lz4": ["lz4", "-c", "-q"], "zstd": ["zstd", "-c", "-q"]}[codec]
    return subprocess.run(tool, input=data, capture_output=True, check=True).stdout


def write_ros1(path, n, per_chunk=2000, compression="none"):
    rng = np.random.default_rng(25)
    conn_header = field(b"topic", b"/imu") + field(b"type", b"sensor_msgs/Imu") + field(b"md5sum", IMU_MD5)
    connection = record([field(b"op", b"\x07"), field(b"conn", struct.pack("<I", 0)), field(b"topic", b"/imu")], conn_header)
    infos = []
    with open(path, "wb") as f:
        f.write(b"#ROSBAG V2.0\n")
        f.write(b"\0" * 4096)  # the bag header, written at the end
        for first in range(0, n, per_chunk):
            k = min(per_chunk, n - first)
            m = np.zeros(k, ROS1_MESSAGE)
            m["hl"], m["l_op"], m["op"], m["opv"] = 38, 4, b"op=", 2
            m["l_conn"], m["conn"], m["l_time"], m["time"] = 9, b"conn=", 13, b"time="
            sec, nsec = stamps(first, k)
            m["tsec"], m["tnsec"], m["sec"], m["nsec"] = sec, nsec, sec, nsec
            m["dl"] = ROS1_MESSAGE.itemsize - 46
            m["seq"] = np.arange(first, first + k)
            m["flen"], m["frame"] = 3, b"imu"
            m["d"] = imu_doubles(k, *values(rng, k))
            body = connection + m.tobytes()
            pos = f.tell()
            f.write(record([field(b"op", b"\x05"), field(b"compression", compression.encode()),
                            field(b"size", struct.pack("<I", len(body)))], compress(body, compression)))
            offsets = len(connection) + np.arange(k, dtype=np.uint32) * ROS1_MESSAGE.itemsize
            index = np.zeros(k, np.dtype([("sec", "<u4"), ("nsec", "<u4"), ("off", "<u4")]))
            index["sec"], index["nsec"], index["off"] = sec, nsec, offsets
            f.write(record([field(b"op", b"\x04"), field(b"ver", struct.pack("<I", 1)), field(b"conn", struct.pack("<I", 0)),
                            field(b"count", struct.pack("<I", k))], index.tobytes()))
            t0 = struct.pack("<II", int(sec[0]), int(nsec[0]))
            t1 = struct.pack("<II", int(sec[-1]), int(nsec[-1]))
            infos.append(record([field(b"op", b"\x06"), field(b"ver", struct.pack("<I", 1)), field(b"chunk_pos", struct.pack("<Q", pos)),
                                 field(b"start_time", t0), field(b"end_time", t1), field(b"count", struct.pack("<I", 1))],
                                struct.pack("<II", 0, k)))
        index_pos = f.tell()
        f.write(connection)
        for info in infos:
            f.write(info)
        header = [field(b"op", b"\x03"), field(b"index_pos", struct.pack("<Q", index_pos)),
                  field(b"conn_count", struct.pack("<I", 1)), field(b"chunk_count", struct.pack("<I", len(infos)))]
        fixed = 4 + sum(len(h) for h in header) + 4
        f.seek(13)
        f.write(record(header, b" " * (4096 - fixed)))


# --- MCAP ----------------------------------------------------------------------------------------

MCAP_MAGIC = b"\x89MCAP0\r\n"
MCAP_MESSAGE = np.dtype([
    ("op", "u1"), ("len", "<u8"), ("channel", "<u2"), ("seq", "<u4"), ("log", "<u8"), ("pub", "<u8"),
    ("encap", "S4"), ("sec", "<i4"), ("nsec", "<u4"), ("flen", "<u4"), ("frame", "S4"), ("d", "<f8", 37)])


def mcap_string(s):
    return struct.pack("<I", len(s)) + s


def mcap_record(op, content):
    return struct.pack("<BQ", op, len(content)) + content


def write_mcap(path, n, per_chunk=3000, compression="", crc=False):
    rng = np.random.default_rng(25)
    with open(path, "wb") as f:
        f.write(MCAP_MAGIC)
        f.write(mcap_record(0x01, mcap_string(b"ros2") + mcap_string(b"gmwm bench")))
        f.write(mcap_record(0x03, struct.pack("<H", 1) + mcap_string(b"sensor_msgs/msg/Imu") + mcap_string(b"ros2msg") +
                            mcap_string(b"std_msgs/Header header\n")))
        f.write(mcap_record(0x04, struct.pack("<HH", 1, 1) + mcap_string(b"/imu") + mcap_string(b"cdr") + struct.pack("<I", 0)))
        for first in range(0, n, per_chunk):
            k = min(per_chunk, n - first)
            m = np.zeros(k, MCAP_MESSAGE)
            m["op"], m["len"], m["channel"] = 5, MCAP_MESSAGE.itemsize - 9, 1
            m["seq"] = np.arange(first, first + k)
            sec, nsec = stamps(first, k)
            t = sec.astype(np.uint64) * np.uint64(10**9) + nsec
            m["log"], m["pub"] = t, t
            m["encap"], m["sec"], m["nsec"], m["flen"], m["frame"] = b"\x00\x01\x00\x00", sec.astype(np.int32), nsec, 4, b"imu\0"
            m["d"] = imu_doubles(k, *values(rng, k))
            records = m.tobytes()
            stored = compress(records, compression)
            check = zlib.crc32(records) if crc else 0
            content = struct.pack("<QQQI", int(t[0]), int(t[-1]), len(records), check) + mcap_string(compression.encode()) + \
                struct.pack("<Q", len(stored)) + stored
            f.write(mcap_record(0x06, content))
        f.write(mcap_record(0x0F, struct.pack("<I", 0)))
        f.write(mcap_record(0x02, struct.pack("<QQI", 0, 0, 0)))
        f.write(MCAP_MAGIC)


WRITERS = {"ulog": write_ulog, "ros1": write_ros1, "mcap": write_mcap}

if __name__ == "__main__":
    if len(sys.argv) != 4 or sys.argv[1] not in WRITERS:
        raise SystemExit(__doc__)
    WRITERS[sys.argv[1]](sys.argv[3], int(float(sys.argv[2])))
