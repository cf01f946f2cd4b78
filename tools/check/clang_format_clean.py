#!/usr/bin/env python3
"""Every C++ file of the repository is laid out as .clang-format says (issue 45).

    clang_format_clean.py [--plant] SOURCE_DIR

The files: every *.cc and *.h under SOURCE_DIR but build trees (a directory holding a
CMakeCache.txt), hidden directories and node_modules. The tool: Debian's clang-format 14
(`clang-format` or `clang-format-14`), the version .clang-format was written for; another
major version lays some constructs out differently, so the check is skipped (exit 77) under
one. Prints every file that differs, with the fix to run, and exits 1; exits 0 when none does.
--plant checks the checker: a badly laid out file in a temporary directory must be found.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

# The major version .clang-format is written for (Debian bookworm's clang-format).
EXPECTED_MAJOR = 14
SKIP = 77


def find_tool():
    for name in ("clang-format", f"clang-format-{EXPECTED_MAJOR}"):
        path = shutil.which(name)
        if path:
            version = subprocess.run([path, "--version"], capture_output=True, text=True).stdout
            m = re.search(r"version (\d+)\.", version)
            if m and int(m.group(1)) == EXPECTED_MAJOR:
                return path, None
            found = version.strip()
    if shutil.which("clang-format"):
        return None, f"clang-format is {found!r}, not version {EXPECTED_MAJOR}: the layout check is skipped"
    return None, ""


def sources(root):
    out = []
    for d, dirs, files in os.walk(root):
        dirs[:] = sorted(x for x in dirs if not x.startswith(".") and x != "node_modules"
                         and not os.path.exists(os.path.join(d, x, "CMakeCache.txt")))
        out += [os.path.join(d, f) for f in sorted(files) if f.endswith((".cc", ".h"))]
    return out


def differing(tool, style_dir, files):
    """The files clang-format would change, formatted with the .clang-format of style_dir."""
    bad = []
    for k in range(0, len(files), 100):
        chunk = files[k:k + 100]
        done = subprocess.run([tool, f"--style=file:{os.path.join(style_dir, '.clang-format')}", "--dry-run",
                               *chunk], capture_output=True, text=True)
        bad += sorted({line.split(":", 1)[0] for line in done.stderr.splitlines() if ": warning:" in line})
    return bad


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--plant", action="store_true")
    ap.add_argument("source_dir")
    a = ap.parse_args()
    tool, why = find_tool()
    if tool is None:
        if why:
            print(why)
            return SKIP
        print("clang-format not found: install Debian's clang-format (apt-get install clang-format)")
        return 1
    root = os.path.abspath(a.source_dir)
    if a.plant:
        with tempfile.TemporaryDirectory() as t:
            with open(os.path.join(t, "planted.cc"), "w") as f:
                f.write("int  planted( int a ){return a;}\n")
            if differing(tool, root, [os.path.join(t, "planted.cc")]) != [os.path.join(t, "planted.cc")]:
                print("the planted badly laid out file was not found")
                return 1
    bad = differing(tool, root, sources(root))
    for path in bad:
        print(f"{os.path.relpath(path, root)}: not as .clang-format lays it out")
    if bad:
        print(f"fix: {os.path.basename(tool)} -i FILE (or git clang-format on a change)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
