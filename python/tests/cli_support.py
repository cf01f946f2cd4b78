"""The command line the Python tests compare against: where it is and how it is run."""
import os
import subprocess

SOURCE = os.environ.get("GMWM_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
CLI = os.path.abspath(os.environ.get("GMWM_CLI_PATH", os.path.join(SOURCE, "build", "gmwm")))


def run(cwd, *args, check=True):
    """`gmwm ARGS...` in folder `cwd`, its output captured; asserts exit 0 unless check=False."""
    done = subprocess.run([CLI, *args], cwd=cwd, capture_output=True, text=True)
    if check:
        assert done.returncode == 0, done.stderr
    return done


def write_fleet(folder, units, truth, odd_unit, odd_model):
    """A fleet manifest (folder/fleet.csv) of `units` simulated units SN1.. of IMU-X, two gyro
    axes of 16384 samples at 100 Hz each (seed k): every unit `truth`, unit `odd_unit`
    `odd_model` (the one that should stand out)."""
    rows = ["path,unit,model,units"]
    for k in range(1, units + 1):
        spec = odd_model if k == odd_unit else truth
        run(folder, "simulate", "--model", spec, "--n", "16384", "--freq", "100", "--signals", "2", "--names",
            "gyro_x,gyro_y", "--seed", str(k), "--output", f"u{k}.csv", "--quiet")
        rows.append(f'u{k}.csv,SN{k},IMU-X,"gyro=rad/s"')
    (folder / "fleet.csv").write_text("\n".join(rows) + "\n")
    return folder / "fleet.csv"

