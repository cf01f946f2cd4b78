#!/usr/bin/env python3
"""Issue 30's fleet benchmark: a simulated fleet of units (WN + RW + AR1 with unit-to-unit
spread, a few planted outlier units) x 6 axes, run by `gmwm fleet` on this machine and on a
Dask LocalCluster of 2 worker processes; the tables compared bit for bit (but the wall times),
the planted units scored against the outlier flags, throughput in units per minute.

    python3 tools/bench/fleet_scale.py --units 500 --log2n 18 --workdir /path/with/20GB --dask

Each unit's three figures are the fleet's median times lognormal factors (N: 8%, K: 15%, B: 10%
one sigma, the spread between units of one part number; truth in truth.csv); the planted units
have one figure far out (planted.csv). Every axis of a unit shares its parameters and draws its
own noise. The recordings are CSV (time + 6 columns, 17 digits: 36 MB per unit at 2^18). Prints
a Markdown report (and writes it with --report PATH).
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import os
import random
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.abspath(os.path.join(HERE, "..", ".."))
AXES = ["gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"]
FREQ = 100.0
# The fleet's median unit (per sample at 100 Hz): N = sqrt(1e-4 / 100) = 1e-3 U/sqrt(Hz); K =
# sqrt(1e-10 * 100) = 1e-4 U/s/sqrt(Hz); a Gauss-Markov bias of correlation time 10 s
# (phi = exp(-1 / (100 * 10))) and variance 1e-6 U^2 (sigma2 per sample = 1e-6 (1 - phi^2)).
WN, RW, PHI, AR1_VAR = 1e-4, 1e-10, math.exp(-1.0 / 1000.0), 1e-6
# One sigma of the unit-to-unit spread of each figure (log scale).
SPREAD = {"N": 0.08, "K": 0.15, "B": 0.10}
# The planted units: (figure, factor on the figure). N and K scale as sqrt of their variance
# parameter; B as sqrt of the AR1's variance.
PLANTS = [("N", 2.0), ("K", 3.0), ("B", 2.5), ("N", 1.8), ("K", 2.5)]


def gmwm(build: str, *args: str, **kw) -> subprocess.CompletedProcess:
    return subprocess.run([os.path.join(build, "gmwm"), *args], check=True, capture_output=True, text=True, **kw)


def unit_model(factors: dict[str, float]) -> str:
    wn = WN * factors["N"] ** 2
    rw = RW * factors["K"] ** 2
    ar1 = AR1_VAR * factors["B"] ** 2 * (1.0 - PHI * PHI)
    return f"AR1(phi={PHI!r},sigma2={ar1!r})+WN(sigma2={wn!r})+RW(gamma2={rw!r})"


def make_fleet(build: str, work: str, units: int, log2n: int, seed: int) -> tuple[list[dict], dict[str, str]]:
    rng = random.Random(seed)
    planted_at = {round((k + 1) * units / (len(PLANTS) + 1)): p for k, p in enumerate(PLANTS)}
    truth, planted = [], {}
    os.makedirs(work, exist_ok=True)
    started = time.monotonic()
    for k in range(1, units + 1):
        factors = {f: math.exp(rng.gauss(0.0, s)) for f, s in SPREAD.items()}
        if k in planted_at:
            figure, factor = planted_at[k]
            factors[figure] *= factor
            planted[f"SN{k:04d}"] = figure
        name = f"u{k:04d}.csv"
        if not os.path.exists(os.path.join(work, name)):
            gmwm(build, "simulate", "--model", unit_model(factors), "--n", str(1 << log2n), "--freq", str(FREQ),
                 "--signals", "6", "--names", ",".join(AXES), "--seed", str(seed * 100000 + k), "--output",
                 os.path.join(work, name), "--quiet")
        truth.append({"unit": f"SN{k:04d}", "path": name, **{f: factors[f] for f in SPREAD}})
    with open(os.path.join(work, "manifest.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["path", "unit", "model"])
        for t in truth:
            w.writerow([t["path"], t["unit"], "IMU-SIM"])
    with open(os.path.join(work, "truth.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["unit", "path", "N", "K", "B", "planted"])
        w.writeheader()
        for t in truth:
            w.writerow({**t, "planted": planted.get(t["unit"], "")})
    print(f"fleet of {units} units x 6 axes x 2^{log2n} written in {time.monotonic() - started:.0f} s", file=sys.stderr)
    return truth, planted


def run_fleet(build: str, work: str, out: str, extra: list[str]) -> float:
    started = time.monotonic()
    gmwm(build, "fleet", "manifest.csv", "--model", "AR1+WN+RW", "--no-cache", "--json", out + ".json", "--csv",
         out + ".csv", "--quiet", *extra, cwd=work)
    return time.monotonic() - started


def without_timings(path: str) -> dict:
    with open(path) as f:
        doc = json.load(f)
    doc.pop("run", None)
    doc.pop("cache", None)
    for r in doc["rows"]:
        r.pop("seconds", None)
    return doc


def score_flags(doc: dict, planted: dict[str, str]) -> dict:
    """Planted units flagged on their figure; false flags among the others (per unit, and per
    unit x axis x figure test)."""
    flagged_on: dict[str, set[str]] = {}
    for r in doc["rows"]:
        for f in r["flags"]:
            flagged_on.setdefault(r["unit"], set()).add(f.split(":", 1)[0])
    normal_units = {r["unit"] for r in doc["rows"]} - set(planted)
    tests = sum(1 for r in doc["rows"] if r["unit"] in normal_units and r["axis"]) * 3
    false_tests = sum(len(r["flags"]) for r in doc["rows"] if r["unit"] in normal_units)
    return {
        "planted_found": sorted(u for u, fig in planted.items() if fig in flagged_on.get(u, set())),
        "planted_missed": sorted(u for u, fig in planted.items() if fig not in flagged_on.get(u, set())),
        "false_units": sorted(u for u in normal_units if u in flagged_on),
        "normal_units": len(normal_units),
        "false_tests": false_tests,
        "tests": tests,
    }


def dask_run(build: str, work: str, workers: int, extra: list[str]) -> float:
    import distributed

    # The workers import gmwm: the build tree's package first on their path (they inherit it).
    # (multiprocessing's spawn hands the workers this interpreter's sys.path, so it goes there too).
    os.environ["PYTHONPATH"] = os.path.join(build, "python") + os.pathsep + os.environ.get("PYTHONPATH", "")
    sys.path.insert(0, os.path.join(build, "python"))

    with distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=None) as cluster:
        return run_fleet(build, work, "dask", ["--scheduler", cluster.scheduler_address, *extra])


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--units", type=int, default=500)
    p.add_argument("--log2n", type=int, default=18)
    p.add_argument("--seed", type=int, default=30)
    p.add_argument("--build", default=os.path.join(SOURCE, "build"))
    p.add_argument("--workdir", required=True, help="a folder with room for the recordings (36 MB a unit at 2^18)")
    p.add_argument("--dask", action="store_true", help="also run on a LocalCluster of 2 worker processes")
    p.add_argument("--extra", default="", help="further gmwm fleet options, e.g. '--joint'")
    p.add_argument("--report", help="write the Markdown report there too")
    p.add_argument("--clean", action="store_true", help="remove the recordings afterwards")
    a = p.parse_args()
    truth, planted = make_fleet(a.build, a.workdir, a.units, a.log2n, a.seed)
    extra = a.extra.split() if a.extra else []
    local_s = run_fleet(a.build, a.workdir, "local", extra)
    local = without_timings(os.path.join(a.workdir, "local.json"))
    s = score_flags(local, planted)
    joint_s = sum(j["seconds"] for j in local.get("joint", []))
    lines = [f"# Fleet of {a.units} simulated units x 6 axes x 2^{a.log2n} samples ({a.workdir})", "",
             f"- local (this machine, {os.cpu_count()} cores): {local_s:.1f} s in all, of which the recordings "
             f"{local_s - joint_s:.1f} s ({a.units / (local_s - joint_s) * 60:.0f} units/min) and the joint models "
             f"{joint_s:.1f} s; failed {local['failed']}",
             f"- planted outliers flagged on their figure: {len(s['planted_found'])} of {len(planted)} "
             f"({', '.join(f'{u} ({planted[u]})' for u in s['planted_found'])}); missed: {s['planted_missed'] or 'none'}",
             f"- false flags: {len(s['false_units'])} of {s['normal_units']} normal units "
             f"({100 * len(s['false_units']) / max(1, s['normal_units']):.2f}%: {', '.join(s['false_units']) or 'none'}); "
             f"{s['false_tests']} of {s['tests']} unit x axis x figure tests "
             f"({100 * s['false_tests'] / max(1, s['tests']):.3f}%)"]
    if a.dask:
        dask_s = dask_run(a.build, a.workdir, 2, extra)
        remote = without_timings(os.path.join(a.workdir, "dask.json"))
        for doc in (remote, local):
            for j in doc.get("joint", []):
                j.pop("seconds", None)
        same = remote == local
        lines.append(f"- Dask LocalCluster, 2 worker processes x 1 thread: {dask_s:.1f} s in all, the recordings "
                     f"{dask_s - joint_s:.1f} s ({a.units / (dask_s - joint_s) * 60:.0f} units/min; the joint models run "
                     f"on the client as locally); table {'identical' if same else 'DIFFERENT'} to the local one (wall "
                     "times aside)")
    for j in local.get("joint", []):
        t = j.get("replicate_test") or {}
        fig = {k: (j.get(k) or {}).get("value") for k in ("N", "K", "B")}
        lines.append(f"- joint model, {j['axis']}: {j['units']} units ({len(j['left_out'])} that stand out left out), "
                     f"{j.get('recommended')}: N {fig['N']:.4g}, K {fig['K']:.4g}, B {fig['B']:.4g} U; shared-theta "
                     f"H = {t.get('heterogeneity', float('nan')):.4g} on {t.get('df_heterogeneity')} df "
                     f"({t.get('calibration')}), p = {t.get('heterogeneity_p_value')}")
    text = "\n".join(lines) + "\n"
    print(text)
    if a.report:
        with open(a.report, "w") as f:
            f.write(text)
    if a.clean:
        shutil.rmtree(a.workdir)
    return 0


if __name__ == "__main__":
    sys.exit(main())
