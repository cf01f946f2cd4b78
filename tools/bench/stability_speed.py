"""Speed of `gmwm stability` against allantools (issue 48), on the same samples in one run.

    python3 tools/bench/stability_speed.py build/gmwm ALLANTOOLS_GIT_DIR [N ...] [--slow N ...] [--kinds K,K]
        [--all K] [--all-full] [--all-direct N ...] [--slow-large N ...]

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

--all K: every kind of KINDS at all taus (every factor 1, 2, ... up to the kind's largest),
measured on K factors spaced evenly over them (both tools given the same list): the time of
every factor is the sum over them, so the ratio over an even sample is the ratio over all
(each tool's total extrapolated by the same count). allantools at all taus of 1e6 samples
would take about half an hour a kind (5e5 factors of O(N) numpy work), at 1e7 about two
months; gmwm's own all-tau run is timed beside (--all-full: the kinds whose every factor it
reads within its bound, stability::factor_work).

--all-direct N ...: ADEV and HDEV at all taus on N samples, every factor by both tools (their
N log N points in all: allantools' 5e5 ADEV factors of 1e6 samples take it about 20 s of
Python, one numpy slice each). An even sample of their factors is mostly fixed costs (the
phase's building), which the 5e5 factors of a whole run share.

--slow-large N ...: the slow kinds at N samples on their three smallest octave factors only
(MTOTDEV, TTOTDEV, HTOTDEV 1, 2, 4; Theo1 10, 20, 40; MTIE 1, 3, 7). allantools reads them
in O(N m) per factor (a Python loop over N windows or terms), gmwm in O(N): the ratio grows
with m, so the ratio at the smallest factors bounds the ratio over the octaves from below.
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


def max_factor(kind, points):
    """gmwm's largest factor on `points` phase points (stability::max_factor)."""
    if kind in ("adev", "oadev", "totdev"):
        return (points - 1) // 2
    if kind in ("hdev", "ohdev", "htotdev"):
        return (points - 1) // 3
    if kind in ("mdev", "tdev", "mtotdev", "ttotdev"):
        return points // 3
    if kind == "theo1":
        return (points - 1) // 2 * 2
    return points - 1


def even_factors(kind, n, k):
    """K factors spaced evenly over the kind's all-tau factors on n frequency samples (to 0.95
    of the largest: allantools stops a little short of gmwm's largest for some kinds)."""
    top = int(0.95 * max_factor(kind, n + 1))
    return sorted({max(1, round(1 + i * (top - 1) / (k - 1))) for i in range(k)})


SMALLEST_OCTAVES = {"theo1": [10, 20, 40], "mtie": [1, 3, 7]}


def record(tmp, n):
    """White noise plus a random walk as fractional frequency at 1 Hz, and its CSV."""
    rng = np.random.default_rng(48)
    y = rng.normal(size=n) + np.cumsum(rng.normal(scale=1e-3, size=n))
    path = os.path.join(tmp, "y.csv")
    np.savetxt(path, y, header="y", comments="", fmt="%.17g")
    return y, path


def compare(at, gmwm, tmp, n, kinds, runs, factors_of=None, label=""):
    """One table row per kind on n samples: at the octave taus, or at factors_of(kind, n)."""
    y, path = record(tmp, n)
    for kind in kinds:
        fn = getattr(at, kind)
        m = factors_of(kind, n) if factors_of else "octave"  # a list of factors, or a tau set both tools name
        at_taus = m if isinstance(m, str) else np.array(m, dtype=float)
        t_at, (taus, dev, _, _) = best(lambda: fn(y, rate=1.0, data_type="freq", taus=at_taus), runs)
        out = os.path.join(tmp, "out.json")
        gmwm_taus = m if isinstance(m, str) else ",".join(repr(0.75 * f if kind == "theo1" else float(f)) for f in m)
        cmd = [gmwm, "stability", path, "--freq", "1", "--kind", kind, "--taus", gmwm_taus, "--json", out, "--quiet"]
        t_dev = float("inf")

        def run_gmwm():
            nonlocal t_dev
            subprocess.run(cmd, check=True)
            with open(out) as f:
                doc = json.load(f)
            t_dev = min(t_dev, doc["run"]["seconds"]["deviations"])  # the best of the runs, as allantools'
            return doc

        t_proc, doc = best(run_gmwm, runs)
        d = doc["columns"][0]["deviations"][kind]
        mine = {f: v for f, v in zip(d["m"], d["value"])}
        at_m = [round(t) for t in taus]  # rate 1: allantools' m is its tau
        diffs = [abs(mine[f] / v - 1) for f, v in zip(at_m, dev) if f in mine and v > 0]
        print(f"| {n:.0e} | {kind}{label} | {t_at:.3f} | {t_dev:.4f} | {t_proc:.3f} | {t_at / t_dev:.1f}x | "
              f"{t_at / t_proc:.1f}x | {max(diffs) if diffs else float('nan'):.1e} ({len(diffs)} taus) |",
              flush=True)


def full_all(gmwm, tmp, n, kinds):
    """gmwm's own run of every factor of the kinds it reads within its bound: its seconds."""
    _, path = record(tmp, n)
    for kind in kinds:
        out = os.path.join(tmp, "all.json")
        r = subprocess.run([gmwm, "stability", path, "--freq", "1", "--kind", kind, "--taus", "all", "--json", out,
                            "--quiet"], capture_output=True, text=True)
        if r.returncode != 0:
            print(f"- {n:.0e} {kind} all taus: refused ({r.stderr.strip()[-90:]})", flush=True)
            continue
        with open(out) as f:
            doc = json.load(f)
        s = doc["run"]["seconds"]
        count = len(doc["columns"][0]["deviations"][kind]["m"])
        print(f"- {n:.0e} {kind} all taus ({count} factors): deviations {s['deviations']:.2f} s, intervals "
              f"{s['intervals']:.2f} s, process {s['total']:.2f} s", flush=True)


def take(rest, flag, default=None):
    """The numbers after `flag` up to the next flag (removed from rest), or default."""
    if flag not in rest:
        return default
    at = rest.index(flag)
    end = next((i for i in range(at + 1, len(rest)) if rest[i].startswith("--")), len(rest))
    values = rest[at + 1:end]
    del rest[at:end]
    return values


def main():
    gmwm, git_dir = sys.argv[1], sys.argv[2]
    rest = sys.argv[3:]
    only = take(rest, "--kinds")
    only = only[0].split(",") if only else None
    every = take(rest, "--all")
    direct = take(rest, "--all-direct")  # every factor by both tools (ADEV and HDEV: N log N points)
    full = take(rest, "--all-full") is not None
    slow_large = [int(float(a)) for a in take(rest, "--slow-large", [])]
    slow = take(rest, "--slow")
    sizes = [int(float(a)) for a in rest] or [10**6]
    slow_sizes = [int(float(a)) for a in slow] if slow is not None else [1000, 4000]
    if slow_large and slow is None:
        slow_sizes = []
    chosen = [k for k in KINDS if not only or k in only]
    chosen_slow = [k for k in SLOW_KINDS if not only or k in only]
    with tempfile.TemporaryDirectory() as tmp:
        at = allantools_from(git_dir, tmp)
        print("| N | kind | allantools (s) | gmwm deviations (s) | gmwm process (s) | ratio (deviations) | "
              "ratio (process) | largest relative difference |")
        print("|---|---|---|---|---|---|---|---|")
        for n in sizes:
            if every:
                k = int(every[0]) if every else 48
                compare(at, gmwm, tmp, n, chosen, RUNS, lambda kind, n, k=k: even_factors(kind, n, k),
                        f" (all taus: {k} of them)")
            else:
                compare(at, gmwm, tmp, n, chosen, RUNS)
        for n in [int(float(a)) for a in direct or []]:
            compare(at, gmwm, tmp, n, [k for k in ("adev", "hdev") if k in chosen], 1, lambda kind, n: "all",
                    " (all taus, every one)")
        for n in slow_sizes:
            compare(at, gmwm, tmp, n, chosen_slow, 1)
        for n in slow_large:
            compare(at, gmwm, tmp, n, chosen_slow, 1, lambda kind, n: SMALLEST_OCTAVES.get(kind, [1, 2, 4]),
                    " (3 smallest octaves)")
        if full:
            for n in sizes:
                full_all(gmwm, tmp, n, chosen)


if __name__ == "__main__":
    main()
