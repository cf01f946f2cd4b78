"""The three-cornered hat on the three shared ADIS16405 recordings (issue 48, item 7).

    python3 tools/bench/stability_hat_real.py build/gmwm [AXIS ...]   (default gyro_x gyro_z)

The folder $GMWM_SHARED_DATA (the ADIS recordings) holds three units' static
recordings of 1e6 samples at 100 Hz. They were recorded separately (no stamps; their slow
components do not move together): not three sensors recorded together, so no hat of theirs
separates a common input. They share no input a deviation sees (Earth's rate is constant), so
their differences are sums of independent noises, and the hat of the three records must give
each unit's own deviation: this checks the separation on real, quantised noise. For each axis
the three units' column side by side (one CSV, --freq 100) goes through `gmwm stability --hat
--kind oadev,mdev`; per kind the table compares each unit's own deviation (its column's) with
its separated one, and counts how often the own one lies inside the hat's interval. Prints
markdown.
"""
import csv
import gzip
import json
import os
import statistics
import subprocess
import sys
import tempfile

UNITS = ["adis_16405_imu1.csv.gz", "adis_16405_imu2.csv.gz", "adis_16405_imu3.csv.gz"]


def shared_folder():
    folder = os.environ.get("GMWM_SHARED_DATA")
    if not folder:
        sys.exit("GMWM_SHARED_DATA is not set to the folder with the ADIS recordings")
    return folder


def axis_side_by_side(axis, into):
    """One CSV with the three units' `axis` as columns unit1, unit2, unit3."""
    readers = [csv.DictReader(gzip.open(os.path.join(shared_folder(), u), "rt")) for u in UNITS]
    path = os.path.join(into, f"{axis}.csv")
    with open(path, "w") as out:
        out.write("unit1,unit2,unit3\n")
        for rows in zip(*readers):
            out.write(",".join(r[axis] for r in rows) + "\n")
    return path


def report(axis, doc):
    for kind, hat in doc["hat"]["deviations"].items():
        print(f"\n{axis}, {kind} (deg/s): each unit's own deviation / its separated one [interval]\n")
        print("| tau (s) | edf | " + " | ".join(doc["hat"]["sensors"]) + " |")
        print("|---|---|---|---|---|")
        inside = given = negative = 0
        ratios = []
        for i, tau in enumerate(hat["tau"]):
            cells = []
            for s, sensor in enumerate(hat["sensors"]):
                own = doc["columns"][s]["deviations"][kind]["value"][i]
                v, lo, hi = sensor["value"][i], sensor["ci_low"][i], sensor["ci_high"][i]
                if sensor["negative"][i]:
                    negative += 1
                    cells.append(f"{own:.4g} / var {sensor['variance'][i]:.2g} < 0")
                else:
                    ratios.append(v / own)
                    cells.append(f"{own:.4g} / {v:.4g}" + (f" [{lo:.3g}, {hi:.3g}]" if lo is not None else ""))
                if lo is not None:
                    given += 1
                    inside += lo <= own <= hi
            edf = hat["edf"][i]
            print(f"| {tau:g} | {edf:.4g} | " + " | ".join(cells) + " |")
        print(f"\nseparated / own: median {statistics.median(ratios):.4f}, {min(ratios):.3f} .. {max(ratios):.3f}; "
              f"own inside the interval {inside} of {given} given ({3 * len(hat['tau'])} in all); "
              f"negative variances {negative}")


def main():
    gmwm = sys.argv[1] if len(sys.argv) > 1 else "build/gmwm"
    axes = sys.argv[2:] or ["gyro_x", "gyro_z"]
    with tempfile.TemporaryDirectory() as folder:
        for axis in axes:
            path = axis_side_by_side(axis, folder)
            done = subprocess.run([gmwm, "stability", path, "--freq", "100", "--hat", "--kind", "oadev,mdev",
                                   "--units", "deg/s", "--json", "-", "--quiet"], capture_output=True, text=True,
                                  check=True)
            report(axis, json.loads(done.stdout))


if __name__ == "__main__":
    main()
