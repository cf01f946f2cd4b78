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
