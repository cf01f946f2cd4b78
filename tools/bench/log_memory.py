#!/usr/bin/env python3
"""Peak memory of `gmwm wv` on large binary logs, with and without `--memory MB` (issue 25):
for each of a PX4 ULog, a ROS 1 bag and an MCAP file of --n messages (written by
tools/bench/imu_logs.py into --dir, deleted afterwards unless --keep), the peak RSS and wall
time of `gmwm wv FILE` in memory and with `--memory 50`, measured with /usr/bin/time -v, and
whether the two WVs are equal to the last bit. Prints a markdown table (the 2026-11-26 run:
tools/bench/results/2026-11-26-binary-log-memory.md; new runs go into a new dated file there).

    /usr/bin/python3 tools/bench/log_memory.py [--n 2e7] [--memory 50] [--dir /tmp/gmwm-logmem]
                                               [--formats ulog,ros1,mcap] [--keep]
"""
import argparse
import json
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
import imu_logs  # noqa: E402
from peak_memory import run_measured  # noqa: E402

LABELS = {"ulog": "PX4 ULog (sensor_combined)", "ros1": "ROS 1 bag (uncompressed chunks)", "mcap": "MCAP (uncompressed chunks)"}
SUFFIX = {"ulog": ".ulg", "ros1": ".bag", "mcap": ".mcap"}


def measure(cli, path, out, *extra):
    rss_mb, seconds, _ = run_measured([cli, "wv", path, "--json", out, "--quiet", *extra])
    return rss_mb * 1024 * 1024, seconds


def levels(path):
    return [c["levels"] for c in json.load(open(path))["columns"]]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=float, default=2e7)
    ap.add_argument("--memory", type=int, default=50)
    ap.add_argument("--dir", default="/tmp/gmwm-logmem")
    ap.add_argument("--formats", default="ulog,ros1,mcap")
    ap.add_argument("--cli", default=os.path.join(ROOT, "build", "gmwm"))
    ap.add_argument("--keep", action="store_true")
    a = ap.parse_args()
    n = int(a.n)
    os.makedirs(a.dir, exist_ok=True)
    rows = []
    for fmt in a.formats.split(","):
        path = os.path.join(a.dir, f"imu_{n}{SUFFIX[fmt]}")
        if not os.path.exists(path):
            t0 = time.perf_counter()
            imu_logs.WRITERS[fmt](path, n)
            print(f"wrote {path} ({os.path.getsize(path) / 1e9:.2f} GB) in {time.perf_counter() - t0:.0f} s", file=sys.stderr)
        full_rss, full_wall = measure(a.cli, path, path + ".json")
        budget_rss, budget_wall = measure(a.cli, path, path + ".mem.json", "--memory", str(a.memory))
        same = levels(path + ".json") == levels(path + ".mem.json")
        rows.append((LABELS[fmt], n, os.path.getsize(path), full_rss, full_wall, budget_rss, budget_wall, same))
        for p in (path + ".json", path + ".mem.json") + (() if a.keep else (path,)):
            os.remove(p)
    print(f"| input | messages | file | peak RSS, in memory | wall | peak RSS, `--memory {a.memory}` | wall | WV equal |")
    print("|---|---|---|---|---|---|---|---|")
    for label, k, size, r0, w0, r1, w1, same in rows:
        print(f"| {label} | {k:.0e} | {size / 1e9:.2f} GB | {r0 / 1e6:.0f} MB | {w0:.1f} s | {r1 / 1e6:.0f} MB | {w1:.1f} s | "
              f"{'yes, bit for bit' if same else 'NO'} |")


if __name__ == "__main__":
    main()
