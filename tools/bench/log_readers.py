#!/usr/bin/env python3
"""Reading robotics logs of 1e6 IMU messages: `gmwm wv` on a ROS 1 bag (uncompressed, lz4,
bz2), a rosbag2 sqlite3 bag and MCAP bags (zstd, lz4), each checked against the same values
in CSV (the WV to the last bit) and timed (median wall time of --runs runs).

    /usr/bin/python3 tools/bench/log_readers.py [--n 1000000] [--dir /tmp/gmwm-logs] [--runs 3]

Writers: ROS 1 bags by Debian python3-rosbag, rosbag2 by Python's sqlite3 with hand-packed
CDR (python/tests/test_rosbag2.py), MCAP by @mcap/core (tools/fixtures/mcap; needs Node and
`npm install` there, skipped with a message otherwise). Files are written once and reused.
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "python", "tests"))


def write_ros1(path, n, compression):
    import test_rosbag1 as r1
    return r1.write_bag(path, n=n, compression=compression)


def write_rosbag2(path, n):
    import test_rosbag2 as r2
    return r2.write_bag(path, n=n)


def write_csv(path, gyro, accel):
    with open(path, "w") as f:
        f.write("gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z\n")
        for g, a in zip(gyro.tolist(), accel.tolist()):
            f.write(",".join(repr(x) for x in (*g, *a)) + "\n")


def wv(cli, path, out, *extra):
    t0 = time.perf_counter()
    r = subprocess.run([cli, "wv", path, "--json", out, "--quiet", *extra], capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if r.returncode != 0:
        raise SystemExit(f"{path}: gmwm wv failed: {r.stderr.strip()}")
    return wall


def levels(path):
    return [c["levels"] for c in json.load(open(path))["columns"]]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=1_000_000)
    ap.add_argument("--dir", default="/tmp/gmwm-logs")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--cli", default=os.path.join(ROOT, "build", "gmwm"))
    a = ap.parse_args()
    os.makedirs(a.dir, exist_ok=True)
    d = lambda name: os.path.join(a.dir, name)  # noqa: E731

    cases = []  # (label, file, csv, writer)
    for comp in ("none", "lz4", "bz2"):
        cases.append((f"ROS 1 bag, {comp}", d(f"imu_{comp}.bag"), d("ros.csv"),
                      lambda p, c=comp: write_ros1(p, a.n, c)))
    cases.append(("rosbag2 sqlite3", d("imu.db3"), d("ros.csv"), lambda p: write_rosbag2(p, a.n)))
    node = shutil.which("node")
    fixtures = os.path.join(ROOT, "tools", "fixtures", "mcap")
    have_mcap = node and os.path.isdir(os.path.join(fixtures, "node_modules"))
    if have_mcap:
        for comp in ("zstd", "lz4"):
            def write_mcap(p, c=comp):
                extra = ["--csv", d("mcap.csv")] if c == "zstd" else []
                subprocess.run([node, os.path.join(fixtures, "write_imu_mcap.mjs"), p, "--n", str(a.n),
                                "--compression", c, "--chunk-size", str(1 << 20), *extra], check=True)
            cases.append((f"MCAP, {comp}", d(f"imu_{comp}.mcap"), d("mcap.csv"), write_mcap))
    else:
        print("MCAP skipped: needs node and `npm install` in tools/fixtures/mcap", file=sys.stderr)

    for label, path, csv, writer in cases:
        if not os.path.exists(path):
            t0 = time.perf_counter()
            result = writer(path)
            print(f"wrote {path} in {time.perf_counter() - t0:.1f} s", file=sys.stderr)
            if result is not None and not os.path.exists(csv):
                write_csv(csv, *result)

    csv_levels = {}
    for csv in sorted({c for _, _, c, _ in cases}):
        wv(a.cli, csv, csv + ".json", "--freq", "200")
        csv_levels[csv] = levels(csv + ".json")
    print(f"| input ({a.n} messages) | size (MB) | `wv` median wall (s), {a.runs} runs | WV equal to the CSV's |")
    print("|---|---|---|---|")
    for label, path, csv, _ in cases:
        walls = [wv(a.cli, path, path + ".json") for _ in range(a.runs)]
        same = levels(path + ".json") == csv_levels[csv]
        print(f"| {label} | {os.path.getsize(path) / 1e6:.0f} | {statistics.median(walls):.2f} | "
              f"{'yes, bit for bit' if same else 'NO'} |")


if __name__ == "__main__":
    main()
