#!/usr/bin/env python3
"""Peak memory and time of `gmwm stability` on a long record, within a memory budget and in
memory (issue 48: "1e8 samples in bounded memory (--memory)"), and whether both runs give the
same document (every value, interval and noise; the "run" timings aside).

    /usr/bin/python3 tools/bench/stability_memory.py [--n 100000000] [--memory 200]
        [--kinds adev,oadev,mdev,tdev,hdev,ohdev,totdev,tierms] [--dir /tmp/gmwm-stability-memory]

The record (white noise plus a random walk, quantised to 1e-3, one column, gzip CSV: about
215 MB for 1e8 samples) is simulated once by `gmwm simulate` and reused. Peak RSS from
/usr/bin/time -v; the run's own seconds (read, deviations, intervals) from its JSON.
"""
import argparse
import json
import os
import subprocess
import sys

from peak_memory import run_measured

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
MODEL = "WN(sigma2=1)+RW(gamma2=1e-6)"
BOUNDED_KINDS = "adev,oadev,mdev,tdev,hdev,ohdev,totdev,tierms"


def simulate(cli, path, n):
    if os.path.exists(path):
        return
    subprocess.run([cli, "simulate", "--model", MODEL, "--n", str(n), "--quantum", "1e-3", "-o", path, "--quiet"],
                   check=True)


def run(cli, path, kinds, extra, out_json):
    rss, wall, _ = run_measured([cli, "stability", path, "--freq", "1", "--kind", kinds, "--json", out_json,
                                 "--quiet"] + extra)
    with open(out_json) as f:
        doc = json.load(f)
    return rss, wall, doc


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=100_000_000)
    ap.add_argument("--memory", type=int, default=200)
    ap.add_argument("--kinds", default=BOUNDED_KINDS)
    ap.add_argument("--dir", default="/tmp/gmwm-stability-memory")
    ap.add_argument("--cli", default=os.path.join(ROOT, "build", "gmwm"))
    a = ap.parse_args()
    os.makedirs(a.dir, exist_ok=True)
    path = os.path.join(a.dir, "record_%d.csv.gz" % a.n)
    simulate(a.cli, path, a.n)
    print("| run | peak memory (MB) | wall (s) | read / deviations / intervals (s) |")
    print("|---|---|---|---|")
    docs = []
    for label, extra in (("--memory %d" % a.memory, ["--memory", str(a.memory)]), ("in memory", [])):
        rss, wall, doc = run(a.cli, path, a.kinds, extra, os.path.join(a.dir, "out.json"))
        s = doc["run"]["seconds"]
        print("| %s | %.0f | %.1f | %.1f / %.1f / %.1f |" % (label, rss, wall, s["read"], s["deviations"],
                                                             s["intervals"]), flush=True)
        doc.pop("run")
        docs.append(doc)
    print("\nthe same document (values, intervals, noises): %s" % ("yes" if docs[0] == docs[1] else "NO"))
    return 0 if docs[0] == docs[1] else 1


if __name__ == "__main__":
    sys.exit(main())
