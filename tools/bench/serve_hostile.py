#!/usr/bin/env python3
"""gmwm serve under hostile load (issue 42's bar): 200 concurrent hostile connections (slow
headers, slow bodies, huge chunked bodies with and without the token, listings of a folder of
200,000 files that are not recordings) while a normal client lists the folder every 100 ms;
its latency (median, 95th percentile, max) and the server's resident memory (now and peak,
from /proc) against the documented cap (docs/serve.md, "Limits and safety").

    python3 tools/bench/serve_hostile.py --gmwm build/gmwm [--connections 200] [--files 200000]
                                         [--seconds 30]

Prints a Markdown table. Standard library only."""

import argparse
import http.client
import os
import shutil
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

# The server's own memory bound under this load, beyond the datasets it holds (none here):
# docs/serve.md, "Limits and safety".
RSS_CAP_MB = 256


def rss_mb(pid, field):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith(field + ":"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


class Attack(threading.Thread):
    """One hostile connection, kept busy until `stop` is set."""

    def __init__(self, kind, port, token, stop):
        super().__init__(daemon=True)
        self.kind, self.port, self.token, self.stop = kind, port, token, stop
        self.sent = 0

    def connect(self):
        s = socket.create_connection(("127.0.0.1", self.port), timeout=30)
        s.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 1 << 16)
        return s

    def run(self):
        host = f"Host: 127.0.0.1:{self.port}\r\n"
        own = host + f"X-Gmwm-Token: {self.token}\r\n"
        while not self.stop.is_set():
            try:
                s = self.connect()
                if self.kind == "slow headers":  # a header byte every 2 s, never finished
                    s.sendall(b"GET /api/files HTTP/1.1\r\n" + host.encode())
                    while not self.stop.is_set():
                        s.sendall(b"X")
                        self.sent += 1
                        time.sleep(2)
                elif self.kind == "slow body":  # with the token: a byte of JSON every 2 s
                    s.sendall(("POST /api/fit HTTP/1.1\r\n" + own +
                               "Content-Type: application/json\r\nContent-Length: 100000\r\n\r\n{").encode())
                    while not self.stop.is_set():
                        s.sendall(b" ")
                        self.sent += 1
                        time.sleep(2)
                elif self.kind in ("huge chunked body", "huge chunked upload without the token"):
                    target = "/api/fit" if self.kind == "huge chunked body" else "/api/upload?name=x.csv"
                    kind = "application/json" if self.kind == "huge chunked body" else "application/octet-stream"
                    head = own if self.kind == "huge chunked body" else host
                    s.sendall((f"POST {target} HTTP/1.1\r\n" + head + f"Content-Type: {kind}\r\n"
                               "Transfer-Encoding: chunked\r\n\r\n").encode())
                    chunk = b"10000\r\n" + b" " * 0x10000 + b"\r\n"
                    while not self.stop.is_set():
                        s.sendall(chunk)  # until the server refuses and closes
                        self.sent += len(chunk)
                elif self.kind == "listing":
                    s.sendall(("GET /api/files HTTP/1.1\r\n" + own + "\r\n").encode())
                    while not self.stop.is_set() and s.recv(1 << 16):
                        pass
                s.close()
            except OSError:
                pass  # refused and closed: open the next one


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--gmwm", required=True)
    ap.add_argument("--connections", type=int, default=200)
    ap.add_argument("--files", type=int, default=200_000)
    ap.add_argument("--seconds", type=float, default=30.0)
    a = ap.parse_args()
    folder = Path(tempfile.mkdtemp(prefix="gmwm-serve-hostile-"))
    subprocess.run([a.gmwm, "simulate", "--model", "WN(sigma2=1e-4)+RW(gamma2=1e-10)", "--n", "100000", "--freq", "100",
                    "--names", "gyro_x", "--output", str(folder / "imu.csv"), "--quiet"], check=True)
    junk = folder / "junk"
    for d in range(a.files // 1000):
        sub = junk / f"{d:04d}"
        sub.mkdir(parents=True)
        for k in range(1000):
            (sub / f"note{k}.log").touch()
    server = subprocess.Popen([a.gmwm, "serve", str(folder), "--port", "0"], stdout=subprocess.PIPE, text=True)
    try:
        url, token = server.stdout.readline().split()[2].split("?token=")
        port = int(url.rstrip("/").rsplit(":", 1)[1])

        def listing():
            c = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
            t0 = time.perf_counter()
            c.request("GET", "/api/files", headers={"X-Gmwm-Token": token})
            r = c.getresponse()
            body = r.read()
            c.close()
            assert r.status == 200 and b"imu.csv" in body, (r.status, body[:200])
            return 1e3 * (time.perf_counter() - t0)

        quiet = [listing() for _ in range(20)]
        rss_before = rss_mb(server.pid, "VmRSS")
        stop = threading.Event()
        kinds = ["slow headers", "slow body", "huge chunked body", "huge chunked upload without the token", "listing"]
        attacks = [Attack(kinds[i % len(kinds)], port, token, stop) for i in range(a.connections)]
        for t in attacks:
            t.start()
        time.sleep(1.0)
        under, rss = [], []
        end = time.time() + a.seconds
        while time.time() < end:
            under.append(listing())
            rss.append(rss_mb(server.pid, "VmRSS"))
            time.sleep(0.1)
        peak = rss_mb(server.pid, "VmHWM")
        stop.set()
        sent = sum(t.sent for t in attacks if "chunked" in t.kind)
        alive = server.poll() is None

        def q(v, p):
            return sorted(v)[min(len(v) - 1, int(p * len(v)))]

        print(f"{a.connections} hostile connections ({', '.join(kinds)}, round robin), {a.files} files that are not "
              f"recordings, {a.seconds:.0f} s; a normal client lists the folder every 100 ms\n")
        print("| measure | value |")
        print("|---|---|")
        print(f"| listing before the attack: median / max | {statistics.median(quiet):.1f} / {max(quiet):.1f} ms |")
        print(f"| listing under the attack: median / 95% / max ({len(under)} listings) | "
              f"{statistics.median(under):.1f} / {q(under, 0.95):.1f} / {max(under):.1f} ms |")
        print(f"| listings over 1 s | {sum(1 for x in under if x > 1000)} of {len(under)} |")
        print(f"| server resident memory before / max during / peak (VmHWM) | {rss_before:.0f} / {max(rss):.0f} / "
              f"{peak:.0f} MB (cap {RSS_CAP_MB} MB) |")
        print(f"| bytes the huge bodies sent before being cut | {sent / 1e6:.1f} MB |")
        print(f"| server still running | {'yes' if alive else 'NO'} |")
        ok = alive and max(under) < 1000.0 and peak < RSS_CAP_MB
        sys.exit(0 if ok else 1)
    finally:
        server.terminate()
        try:
            server.wait(timeout=30)
        except subprocess.TimeoutExpired:
            server.kill()
        shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
