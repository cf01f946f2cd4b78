#!/usr/bin/env python3
"""The pictures of docs/python.md's "Plots": each result's .plot() on the shipped example
(data/example_imu6.csv.gz, its Kalibr file and a fleet of simulated units), written to
docs/images/python_<name>.png. Run from the repository's root after the build:

    PYTHONPATH=build/python python3 tools/docs/plot_gallery.py [OUTPUT_FOLDER]
"""
import os
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import gmwm  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CLI = os.environ.get("GMWM_CLI_PATH", os.path.join(ROOT, "build", "gmwm"))
EXAMPLE = os.path.join(ROOT, "data", "example_imu6.csv.gz")
# The pictures' resolution: sharp on a screen, a few tens of kilobytes each.
DPI = 80


def save(ax, folder, name):
    axes = ax if isinstance(ax, tuple) else [ax]
    fig = (axes[0] if not hasattr(axes[0], "flat") else axes[0].flat[0]).figure
    fig.tight_layout()
    path = os.path.join(folder, f"python_{name}.png")
    fig.savefig(path, dpi=DPI)
    matplotlib.pyplot.close(fig)
    print(path)


def main(folder):
    os.makedirs(folder, exist_ok=True)
    imu = gmwm.read(EXAMPLE)
    gyro = imu["gyro_x"]
    save(gmwm.wv(gyro, units="rad/s").plot(), folder, "wv")
    save(gmwm.allan(gyro, units="rad/s").plot(), folder, "allan")
    save(gmwm.fit(gyro, "AR1+WN+RW", units="rad/s").plot(), folder, "fit")
    save(gmwm.select(gyro, "2*AR1+WN+RW", units="rad/s")[0].plot(), folder, "select")
    kalibr = os.path.join(ROOT, "data", "adis16405_imu.yaml")
    save(gmwm.gap(imu[["gyro_x"]], kalibr=kalibr, units="rad/s", replicates=100).plot()[0], folder, "gap")
    with tempfile.TemporaryDirectory() as work:
        subprocess.run([CLI, "select", EXAMPLE, "--model", "WN+RW", "--units", "gyro=rad/s,accel=m/s^2", "--json",
                        "select.json", "--quiet"], cwd=work, check=True)
        nav = gmwm.nav(os.path.join(work, "select.json"), ["truth", "wnrw", "wnrw*3"], horizon=120.0,
                       outages=[(40.0, 60.0)])
        save(nav.plot(), folder, "nav")
        rows = ["path,unit,model,units"]
        for k in range(1, 7):
            spec = "WN(sigma2=4e-7)+RW(gamma2=1e-14)" if k == 4 else "WN(sigma2=1e-7)+RW(gamma2=1e-14)"
            subprocess.run([CLI, "simulate", "--model", spec, "--n", "65536", "--freq", "100", "--signals", "3",
                            "--names", "gyro_x,gyro_y,gyro_z", "--seed", str(k), "--output", f"u{k}.csv", "--quiet"],
                           cwd=work, check=True)
            rows.append(f'u{k}.csv,SN{k},IMU-X,"gyro=rad/s"')
        with open(os.path.join(work, "fleet.csv"), "w") as f:
            f.write("\n".join(rows) + "\n")
        save(gmwm.fleet(os.path.join(work, "fleet.csv"), model="WN+RW", cache=None).plot(), folder, "fleet")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "docs", "images"))
