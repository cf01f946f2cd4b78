#!/usr/bin/env python3
"""gmwm serve's latency on a real recording (issue 31's bars): the page's first answer, opening
a 1e6-sample six-axis recording, and a fit of one 1e6-sample axis from the request to its
result, each timed over repeated requests against the program's own server on loopback; the
same fit by the command line beside it (the server's work is the CLI's, minus the reading).

    python3 tools/bench/serve_latency.py --gmwm build/gmwm --data $GMWM_SHARED_DATA [--runs 20]

Prints a Markdown table (median, min, max in ms). Standard library only."""

import argparse
import json
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.request
from pathlib import Path

RECORDING = "adis_16405_imu1.csv.gz"  # 1,000,000 rows x 6 axes at 100 Hz (the recordings' README)


TOKEN = ""  # the server's access token, from the address it prints


def request(url, body=None, method=None):
    data = None if body is None else json.dumps(body).encode()
    req = urllib.request.Request(url, data=data, method=method or ("POST" if data else "GET"),
                                 headers={"Content-Type": "application/json", "X-Gmwm-Token": TOKEN})
    with urllib.request.urlopen(req, timeout=120) as r:
        return r.read()


def job(url, endpoint, body, poll=0.005):
    """Submits a job and polls until it ends; its status."""
    j = json.loads(request(url + endpoint, body))["job"]
    while True:
        s = json.loads(request(url + "api/jobs/" + j))
        if s["state"] not in ("queued", "running"):
            return s
        time.sleep(poll)


def timed(f, runs):
    out = []
    for _ in range(runs):
        t0 = time.perf_counter()
        f()
        out.append(1e3 * (time.perf_counter() - t0))
    return out


def row(name, ms):
    return f"| {name} | {statistics.median(ms):.1f} | {min(ms):.1f} | {max(ms):.1f} | {len(ms)} |"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--gmwm", required=True)
    ap.add_argument("--data", required=True)
    ap.add_argument("--runs", type=int, default=20)
    ap.add_argument("--model", default="AR1+WN+RW")
    a = ap.parse_args()
    folder = Path(tempfile.mkdtemp(prefix="gmwm-serve-bench-"))
    shutil.copy(Path(a.data) / RECORDING, folder / RECORDING)
    server = subprocess.Popen([a.gmwm, "serve", str(folder), "--port", "0"], stdout=subprocess.PIPE, text=True)
    try:
        global TOKEN
        url, TOKEN = server.stdout.readline().split()[2].split("?token=")
        page = timed(lambda: request(url), a.runs)
        vega = timed(lambda: request(url + "vega.js"), a.runs)
        opened = []
        dataset = None

        def open_it():
            nonlocal dataset
            dataset = json.loads(request(url + "api/open", {"file": RECORDING, "freq": 100}))["dataset"]

        opened = timed(open_it, max(3, a.runs // 4))
        body = {"dataset": dataset, "column": "gyro_x", "model": a.model}
        states = []
        fits = timed(lambda: states.append(job(url, "api/fit", body)["state"]), a.runs)
        assert set(states) == {"done"}, states
        cli = timed(lambda: subprocess.run([a.gmwm, "fit", str(folder / RECORDING), "--freq", "100", "--columns",
                                            "gyro_x", "--model", a.model, "--quiet"], check=True),
                    max(3, a.runs // 4))
    finally:
        server.terminate()
        server.wait(timeout=30)
        shutil.rmtree(folder, ignore_errors=True)
    print(f"gmwm serve on loopback, {RECORDING} (1e6 samples per axis), model {a.model}\n")
    print("| request | median ms | min | max | runs |\n|---|---|---|---|---|")
    print(row("GET / (the page)", page))
    print(row("GET /vega.js (Vega's modules, deferred)", vega))
    print(row("POST /api/open (read the 6-axis gzip CSV)", opened))
    print(row("fit of one axis: POST /api/fit to its result (5 ms polls)", fits))
    print(row("gmwm fit --columns gyro_x (the CLI, reading included)", cli))
    return 0


if __name__ == "__main__":
    sys.exit(main())
