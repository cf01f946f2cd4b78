"""Speed of `gmwm stability` against allantools (issue 48), on the same samples in one run.

    python3 tools/bench/stability_speed.py build/gmwm ALLANTOOLS_GIT_DIR [N ...] [--slow N ...] [--kinds K,K]

ALLANTOOLS_GIT_DIR: a clone of github.com/aewallin/allantools (its package is imported from
a copy of that tree; run with Debian's numpy and scipy). For each N (default 1e6): white noise
plus a random walk as fractional frequency at 1 Hz, every kind at the octave taus: allantools'
computation alone (its function on the numpy array, best of 3), gmwm's deviations alone (the
JSON's run.seconds.deviations, best of 3) and gmwm's whole process (reading the CSV included, best of
3), and the largest relative difference of the two values where both give one (the oracle of
the comparison: the same numbers). Prints a markdown table.

The total deviations, Theo1 and MTIE (SLOW_KINDS) are compared at the sizes after --slow (default
1000 and 4000): allantools reads them window by window (O(N m) per tau, 40 s for MTOTDEV's
octaves at 4000 samples; MTIE over every window: more than 5 minutes for its octaves at 1e6), so
at 1e6 it would take hours to days.
"""
import json
import os
import subprocess
import sys
import tarfile
import tempfile
import time

import numpy as np

KINDS = ["adev", "oadev", "mdev", "tdev", "hdev", "ohdev", "totdev", "tierms"]
SLOW_KINDS = ["mtotdev", "ttotdev", "htotdev", "theo1", "mtie"]
RUNS = 3


def allantools_from(git_dir, into):
    """Imports allantools from a copy of the clone's tree (no install, nothing downloaded)."""
    archive = os.path.join(into, "allantools.tar")
    subprocess.run(["git", "--git-dir", git_dir, "archive", "-o", archive, "HEAD", "allantools"], check=True)
    with tarfile.open(archive) as t:
        t.extractall(into)
    sys.path.insert(0, into)
    import allantools  # noqa: E402  (the copy just made)
    return allantools


def best(f, runs=RUNS):
    times = []
    out = None
    for _ in range(runs):
        t = time.perf_counter()
        out = f()
        times.append(time.perf_counter() - t)
    return min(times), out


def compare(at, gmwm, tmp, n, kinds, runs):
    """One table row per kind on n samples (white noise plus a random walk, 1 Hz)."""
    rng = np.random.default_rng(48)
    y = rng.normal(size=n) + np.cumsum(rng.normal(scale=1e-3, size=n))
    path = os.path.join(tmp, "y.csv")
    np.savetxt(path, y, header="y", comments="", fmt="%.17g")
    for kind in kinds:
        fn = getattr(at, kind)
        t_at, (taus, dev, _, _) = best(lambda: fn(y, rate=1.0, data_type="freq", taus="octave"), runs)
        out = os.path.join(tmp, "out.json")
        cmd = [gmwm, "stability", path, "--freq", "1", "--kind", kind, "--json", out, "--quiet"]
        t_dev = float("inf")

        def run_gmwm():
            nonlocal t_dev
            subprocess.run(cmd, check=True)
            with open(out) as f:
                doc = json.load(f)
            t_dev = min(t_dev, doc["run"]["seconds"]["deviations"])  # the best of the runs, as allantools'
            return doc

        t_proc, doc = best(run_gmwm, RUNS)
        d = doc["columns"][0]["deviations"][kind]
        mine = {round(t, 9): v for t, v in zip(d["tau"], d["value"])}
        diffs = [abs(mine[round(t, 9)] / v - 1) for t, v in zip(taus, dev) if round(t, 9) in mine and v > 0]
        print(f"| {n:.0e} | {kind} | {t_at:.3f} | {t_dev:.4f} | {t_proc:.3f} | {t_at / t_dev:.1f}x | "
              f"{t_at / t_proc:.1f}x | {max(diffs) if diffs else float('nan'):.1e} ({len(diffs)} taus) |",
              flush=True)


def main():
    gmwm, git_dir = sys.argv[1], sys.argv[2]
    rest = sys.argv[3:]
    only = None  # --kinds a,b: those kinds only
    if "--kinds" in rest:
        at_kinds = rest.index("--kinds")
        only = rest[at_kinds + 1].split(",")
        del rest[at_kinds:at_kinds + 2]
    slow_at = rest.index("--slow") if "--slow" in rest else len(rest)
    sizes = [int(float(a)) for a in rest[:slow_at]] or [10**6]
    slow_sizes = [int(float(a)) for a in rest[slow_at + 1:]] or [1000, 4000]
    with tempfile.TemporaryDirectory() as tmp:
        at = allantools_from(git_dir, tmp)
        print("| N | kind | allantools (s) | gmwm deviations (s) | gmwm process (s) | ratio (deviations) | "
              "ratio (process) | largest relative difference |")
        print("|---|---|---|---|---|---|---|---|")
        for n in sizes:
            compare(at, gmwm, tmp, n, [k for k in KINDS if not only or k in only], RUNS)
        for n in slow_sizes:
            compare(at, gmwm, tmp, n, [k for k in SLOW_KINDS if not only or k in only], 1)


if __name__ == "__main__":
    main()
