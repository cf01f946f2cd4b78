#!/usr/bin/env python3
"""Seeds of the binary readers' fuzz targets (tests/fuzz/corpus/{ulog,rosbag1,mcap,cdr}/seed_*):
valid small files of every layout and codec, so that the fuzzers start deep inside the formats,
written by tools/bench/imu_logs.py (independent of gmwm's readers).

    /usr/bin/python3 tools/fuzz/make_binary_seeds.py        # needs the lz4 and zstd programs
"""
import os
import struct
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "tools", "bench"))
import imu_logs  # noqa: E402

CORPUS = os.path.join(ROOT, "tests", "fuzz", "corpus")


def written(writer, *args, **kwargs):
    with tempfile.NamedTemporaryFile(delete=False) as t:
        path = t.name
    writer(path, *args, **kwargs)
    with open(path, "rb") as f:
        data = f.read()
    os.remove(path)
    return data


def ulog_variety():
    """sensor_combined, two sensor_gyro instances (nested and padded formats), a logged
    string, a re-subscription under a new msg_id and an unsubscription."""
    m = imu_logs.ulog_message
    out = b"ULog\x01\x12\x35\x01" + struct.pack("<Q", 1_000_000)
    out += m("F", b"vec3:float x;float y;float z;")
    out += m("F", b"sensor_gyro:uint64_t timestamp;vec3 v;float x;float y;float z;uint8_t[4] _padding0;")
    out += m("F", imu_logs.ULOG_FORMAT)
    out += m("A", struct.pack("<BH", 0, 0) + b"sensor_combined")
    out += m("A", struct.pack("<BH", 0, 1) + b"sensor_gyro")
    out += m("A", struct.pack("<BH", 1, 2) + b"sensor_gyro")
    for i in range(40):
        if i == 20:
            out += m("A", struct.pack("<BH", 0, 3) + b"sensor_combined")
            out += m("R", struct.pack("<H", 0))
            out += m("L", struct.pack("<BQ", ord("6"), 1_000_000 + 5000 * i) + b"[logger] restart")
        ts = 1_000_000 + 5000 * i
        out += m("D", struct.pack("<HQ3fIi3fI4B", 3 if i >= 20 else 0, ts, i / 64, -i / 64, 1 + i % 3, 5000, 0,
                                  0.1 * (i % 5), i / 1000, 9.81 + (i % 3) / 100, 5000, 0, 0, 0, 0))
        for k in (1, 2):
            out += m("D", struct.pack("<HQ3f3f4B", k, ts + 7, 0.0, 0.0, 0.0, k + i / 32, i % 3, 0.5 + i / 100, 0, 0, 0, 0))
    return out


def main():
    seeds = {
        "ulog": {"seed_sensor_combined.ulg": written(imu_logs.write_ulog, 64), "seed_variety.ulg": ulog_variety()},
        "rosbag1": {f"seed_{c}.bag": written(imu_logs.write_ros1, 40, per_chunk=16, compression=c)
                    for c in ("none", "bz2", "lz4")},
        "mcap": {f"seed_{c or 'none'}.mcap": written(imu_logs.write_mcap, 40, per_chunk=16, compression=c, crc=c == "zstd")
                 for c in ("", "lz4", "zstd")},
    }
    mcap = seeds["mcap"]["seed_none.mcap"]
    first = mcap.index(b"\x00\x01\x00\x00")  # the first message's CDR
    seeds["cdr"] = {"seed_imu.cdr": mcap[first:first + 316]}
    for target, files in seeds.items():
        os.makedirs(os.path.join(CORPUS, target), exist_ok=True)
        for name, data in files.items():
            with open(os.path.join(CORPUS, target, name), "wb") as f:
                f.write(data)
            print(f"{target}/{name}: {len(data)} bytes")


if __name__ == "__main__":
    main()
