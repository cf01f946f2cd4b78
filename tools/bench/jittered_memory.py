#!/usr/bin/env python3
"""Peak memory of `gmwm wv` on a long record with jittery nanosecond timestamps (issue 25):
each step differs (more distinct steps than the reader's step table), so the reader keeps a
list of steps, 8 bytes a row; under `--memory MB` that list goes to a temporary file with
the columns. Prints peak RSS (from /usr/bin/time -v) and wall time with and without the
budget, and checks that both runs give the same JSON.

    /usr/bin/python3 tools/bench/jittered_memory.py [--n 20000000] [--memory 50] [--dir /tmp/gmwm-jitter]

The file (about 0.8 GB for 2e7 rows) is written once with numpy and reused.
"""
import argparse
import json
import os
import sys

import numpy as np

from peak_memory import run_measured

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def write_record(path, n, seed=20261126):
    """n rows at 200 Hz: timestamps in ns with +-0.4 ms of uniform jitter, one signal."""
    rng = np.random.default_rng(seed)
    chunk = 1_000_000
    t = 1_700_000_000_000_000_000
    with open(path, "w") as f:
        f.write("timestamp [ns],gyro_x\n")
        for start in range(0, n, chunk):
            m = min(chunk, n - start)
            steps = 5_000_000 + rng.integers(-400_000, 400_001, size=m)
            stamps = t + np.cumsum(steps) - steps[0]
            t = int(stamps[-1]) + 5_000_000
            x = rng.standard_normal(m) * 1e-3 + np.cumsum(rng.standard_normal(m)) * 1e-6
            f.write("".join("%d,%.9e\n" % (s, v) for s, v in zip(stamps.tolist(), x.tolist())))


def run(cli, path, extra, out_json):
    rss, wall, _ = run_measured([cli, "wv", path, "--json", out_json, "--quiet"] + extra)
    return rss, wall


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=20_000_000)
    ap.add_argument("--memory", type=int, default=50)
    ap.add_argument("--dir", default="/tmp/gmwm-jitter")
    ap.add_argument("--cli", default=os.path.join(ROOT, "build", "gmwm"))
    a = ap.parse_args()
    os.makedirs(a.dir, exist_ok=True)
    path = os.path.join(a.dir, "jitter_%d.csv" % a.n)
    if not os.path.exists(path):
        write_record(path, a.n)
    size_mb = os.path.getsize(path) / 1e6
    rows = []
    for label, extra in (("in memory", []), ("--memory %d" % a.memory, ["--memory", str(a.memory)])):
        out = os.path.join(a.dir, "wv_%s.json" % ("budget" if extra else "memory"))
        rss, wall = run(a.cli, path, extra, out)
        rows.append((label, rss, wall, out))
    docs = []
    for _, _, _, out in rows:
        with open(out) as f:
            doc = json.load(f)
        doc.pop("run", None)
        docs.append(doc)
    same = docs[0] == docs[1]
    print("| rows | file | run | peak RSS | wall |")
    print("|---|---|---|---|---|")
    for label, rss, wall, _ in rows:
        print("| %.0e | %.0f MB | `wv` %s | %.0f MB | %.1f s |" % (a.n, size_mb, label, rss, wall))
    print("identical JSON:", same)
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
