"""Peak memory and wall time of one command, the one way the memory benchmarks measure them
(jittered_memory.py, log_memory.py, stability_memory.py): /usr/bin/time -v's "Maximum
resident set size" and a monotonic clock around the run."""
import re
import subprocess
import sys
import time


def run_measured(cmd):
    """Runs cmd (a list) under /usr/bin/time -v; exits naming the command when it fails.
    Returns (peak resident memory in MB, wall seconds, the completed process)."""
    t0 = time.monotonic()
    done = subprocess.run(["/usr/bin/time", "-v"] + list(cmd), capture_output=True, text=True)
    wall = time.monotonic() - t0
    if done.returncode != 0:
        sys.exit(f"{' '.join(cmd)}: exit {done.returncode}: {done.stderr.strip()[-2000:]}")
    rss_kb = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", done.stderr).group(1))
    return rss_kb / 1024.0, wall, done
