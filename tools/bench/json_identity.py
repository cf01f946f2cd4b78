#!/usr/bin/env python3
"""Every command's JSON, before and after a change (issue 29 acceptance: a re-cut of the code
must not change a number).

Runs the same commands with two `gmwm` programs (e.g. one built at the commit before the
change in a `git worktree`, one at the change) on the shipped example and, when
GMWM_SHARED_DATA names the folder with them, on the three ADIS16405 units and cont_imu1, and
compares the JSON documents without their "run" object (timings, host, argv). Prints one
line per command and data set, and every differing path for the first few differences.

Usage: [GMWM_SHARED_DATA=DIR] python3 tools/bench/json_identity.py [--rtol X] [--only LABEL,...]
       BEFORE/gmwm AFTER/gmwm
Exit 0 when every document is identical, or with --rtol X when every number (also the numbers
inside strings) is within X of the other side relative to the larger magnitude; each document
then reports its largest relative difference. --only runs the commands whose labels start with
one of the given prefixes (e.g. --only gap).
"""
import json
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "../..")
EXAMPLE = os.path.join(ROOT, "data", "example_imu6.csv.gz")
KALIBR = os.path.join(ROOT, "data", "adis16405_imu.yaml")
DATASHEET = os.path.join(ROOT, "data", "adis16405_datasheet.yaml")


def data_sets():
    """(name, path, options that read it) per data set."""
    sets = [("example", EXAMPLE, ["--units", "gyro=rad/s,accel=m/s^2"])]
    shared = os.environ.get("GMWM_SHARED_DATA")
    if shared and os.path.isdir(shared):
        for u in (1, 2, 3):
            sets.append(("adis%d" % u, os.path.join(shared, "adis_16405_imu%d.csv.gz" % u),
                         ["--freq", "100", "--units", "gyro=deg/s,accel=g"]))
        sets.append(("cont_imu1", os.path.join(shared, "cont_imu1.csv.gz"), ["--freq", "100", "--units", "gyro=rad/s"]))
    return sets


def commands(path, read):
    """(label, arguments before --json) per command; {sel} stands for the select result."""
    return [
        ("wv", ["wv", path] + read),
        ("wv --adev", ["wv", path, "--adev"] + read),
        ("wv --robust", ["wv", path, "--robust"] + read),
        ("wv --robust bisquare", ["wv", path, "--robust", "--estimator", "bisquare"] + read),
        ("fit", ["fit", path, "--model", "AR1+WN+RW"] + read),
        ("select", ["select", path, "--model", "2*AR1+WN+RW"] + read),
        ("gap --datasheet", ["gap", path, "--datasheet", DATASHEET, "--replicates", "40"] + read),
        ("gap --kalibr", ["gap", path, "--kalibr", KALIBR, "--replicates", "40"] + read),
        # The output path relative: each side runs in a folder of its own.
        ("export kalibr", ["export", "{sel}", "--format", "kalibr", "--output", "imu.yaml"]),
        ("plan", ["plan", "{sel}"]),
        ("nav", ["nav", "--truth", "{sel}", "--horizon", "120", "--outage", "60:90"]),
    ]


def run(gmwm, args, out, cwd):
    r = subprocess.run([gmwm] + args + ["--json", out, "--quiet"], cwd=cwd, capture_output=True, text=True)
    if r.returncode != 0:
        return None, "exit %d: %s" % (r.returncode, r.stderr.strip()[:200])
    with open(out) as f:
        doc = json.load(f)
    doc.pop("run", None)
    return doc, ""


NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


class Tolerance:
    """Numbers within rtol of each other (relative to the larger magnitude) count as equal;
    `largest` keeps the largest relative difference seen."""

    def __init__(self, rtol):
        self.rtol, self.largest = rtol, 0.0

    def close(self, a, b):
        if a == b:
            return True
        scale = max(abs(a), abs(b))
        rel = abs(a - b) / scale if scale > 0 else 0.0
        if rel == rel:  # not NaN
            self.largest = max(self.largest, rel)
        return rel <= self.rtol

    def strings(self, a, b):
        if NUMBER.sub("#", a) != NUMBER.sub("#", b):
            return False
        return all(self.close(float(x), float(y)) for x, y in zip(NUMBER.findall(a), NUMBER.findall(b)))


def differences(a, b, path="", out=None, limit=5, tol=None):
    out = [] if out is None else out
    if len(out) >= limit:
        return out
    numeric = (int, float)
    if tol and isinstance(a, numeric) and isinstance(b, numeric) and not isinstance(a, bool) and not isinstance(b, bool):
        if not tol.close(float(a), float(b)):
            out.append("%s: %r vs %r" % (path or "/", a, b))
    elif type(a) is not type(b):
        out.append("%s: %r vs %r" % (path or "/", a, b))
    elif isinstance(a, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                out.append("%s/%s: only in %s" % (path, k, "before" if k in a else "after"))
            else:
                differences(a[k], b[k], path + "/" + k, out, limit, tol)
    elif isinstance(a, list):
        if len(a) != len(b):
            out.append("%s: %d vs %d items" % (path or "/", len(a), len(b)))
        for i, (x, y) in enumerate(zip(a, b)):
            differences(x, y, "%s[%d]" % (path, i), out, limit, tol)
    elif isinstance(a, str) and tol:
        if not tol.strings(a, b):
            out.append("%s: %r vs %r" % (path or "/", a, b))
    elif a != b:
        out.append("%s: %r vs %r" % (path or "/", a, b))
    return out


def main():
    args, rtol, only = sys.argv[1:], None, None
    while args and args[0].startswith("--"):
        if args[0] == "--rtol" and len(args) > 1:
            rtol, args = float(args[1]), args[2:]
        elif args[0] == "--only" and len(args) > 1:
            only, args = args[1].split(","), args[2:]
        else:
            break
    if len(args) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    before, after = (os.path.abspath(p) for p in args)
    ok = True
    for name, path, read in data_sets():
        with tempfile.TemporaryDirectory() as d:
            sel = os.path.join(d, "sel.json")
            # One select result (the before program's) that both sides' export, plan and nav read.
            run(before, ["select", path, "--model", "2*AR1+WN+RW"] + read, sel, d)
            for label, args in commands(path, read):
                if only and not any(label.startswith(o) for o in only):
                    continue
                docs = []
                for side, gmwm in (("before", before), ("after", after)):
                    sub = os.path.join(d, side)
                    os.makedirs(sub, exist_ok=True)
                    a = [x.replace("{sel}", sel) for x in args]
                    docs.append(run(gmwm, a, os.path.join(sub, "out.json"), sub))
                (x, ex), (y, ey) = docs
                note = ""
                if ex or ey:
                    same = ex == ey
                    why = "before: %s; after: %s" % (ex or "ok", ey or "ok")
                    note = " (both refused the same way: %s)" % ex[:80] if same else ""
                else:
                    tol = Tolerance(rtol) if rtol is not None else None
                    diff = differences(x, y, tol=tol)
                    same, why = not diff, "; ".join(diff)
                    if tol and tol.largest > 0.0:
                        note = " (largest relative difference %.2g)" % tol.largest
                ok = ok and same
                verdict = ("within %g" % rtol if rtol is not None and note else "identical") + note
                print("%-10s %-16s %s%s" % (name, label, verdict if same else "DIFFERENT", "" if same else ": " + why))
    print("json_identity: %s" % ("pass" if ok else "FAIL"))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
