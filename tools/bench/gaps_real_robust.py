#!/usr/bin/env python3
"""The robust WV and fit on the shipped ADIS16405 units with samples removed (issue 47).

The records of tools/bench/gaps_real.py (each unit complete, and with 5% of its samples removed
in bursts of 1..200 samples; the same seeds): `gmwm wv --robust` and `gmwm fit --robust --model
AR1+WN+RW+QN` on both. Per axis: how many of the gappy record's robust levels lie inside the
complete record's robust 95% interval (the bar: all of them), the largest level difference,
and the noise figures N, K, B written (and the data's own read-off) relative to the complete
record's.

Usage: GMWM_SHARED_DATA=DIR python3 tools/bench/gaps_real_robust.py [build/gmwm]
Prints markdown; exit 0 when every level of every axis is inside.
"""
import json
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gaps_real as g  # noqa: E402  (the records, the program and its units)


def columns(folder, args):
    doc = json.loads(g.run(args + ["--units", g.UNITS, "--json", "-", "--quiet"], folder).stdout)
    return {c["name"]: c for c in doc["columns"]}


def main():
    if not g.DATA or not os.path.isdir(g.DATA):
        print("gaps_real_robust.py: GMWM_SHARED_DATA does not name the folder of the ADIS recordings; nothing run")
        return 77
    ok = True
    print("| unit | axis | robust levels inside the complete record's interval | largest level difference | "
          "N written (data's) | K written (data's) | B written (data's) |")
    print("|---|---|---|---|---|---|---|")
    for unit in ("imu1", "imu2", "imu3"):
        src = os.path.join(g.DATA, f"adis_16405_{unit}.csv.gz")
        with tempfile.TemporaryDirectory() as folder:
            g.write_records(src, folder, seed=int(unit[-1]))
            wv = {n: columns(folder, ["wv", n + ".csv.gz", "--robust"]) for n in ("full", "gappy")}
            fit = {n: columns(folder, ["fit", n + ".csv.gz", "--robust", "--model", g.MODEL]) for n in ("full", "gappy")}
        for axis, c in wv["full"].items():
            full, gappy = c["levels"], wv["gappy"][axis]["levels"]
            inside = sum(1 for a, b in zip(gappy, full) if b["ci_low"] <= a["wv"] <= b["ci_high"])
            ok = ok and inside == len(full) == len(gappy)
            worst = max(abs(a["wv"] / b["wv"] - 1) for a, b in zip(gappy, full))
            cells = []
            for key, _ in g.FIGURES:
                f, h = fit["full"][axis]["noise_figures"][key], fit["gappy"][axis]["noise_figures"][key]
                cells.append(f"{h['value'] / f['value'] - 1:+.1%} ({h['data']['value'] / f['data']['value'] - 1:+.1%})")
            print(f"| {unit} | {axis} | {inside}/{len(full)} | {worst:.1%} | " + " | ".join(cells) + " |", flush=True)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
