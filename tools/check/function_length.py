#!/usr/bin/env python3
"""No function in the given folders is longer than a limit (issue 29: 80 lines in pipeline/
and tools/): a long procedure reads as a pipeline of named stages, each a function.

    function_length.py [--limit 80] [--plant] [--allow FILE] DIR ...

A function is a definition at namespace level, as clang-format (.clang-format, Google style)
lays it out: its head starts at column 0 and ends with '{' at the end of a line (a head may
span lines), its body ends with the first '}' at column 0. Its length counts the lines from
the head's last line to the one before the closing brace, as clang-tidy's
readability-function-size counts them (LineThreshold; lambdas inside counted in their
function; the two agree on this repository). Prints every function over the limit as
FILE:LINE: NAME has N lines (limit L) and exits 1; exits 0 when none is.
--plant checks the checker: a planted long function in a temporary file must be found.
--allow FILE: the functions still over the limit, one per line as "PATH NAME LINES" (PATH
relative to the current directory, LINES the length it may not exceed); a list that may only
shrink: an entry whose function is gone or back under the limit fails until it is removed,
and a listed function longer than its LINES fails too.
"""
import argparse
import os
import re
import sys
import tempfile

HEAD_START = re.compile(r"^[A-Za-z_~][^;]*$")          # a type or name at column 0, no ';'
NOT_A_FUNCTION = re.compile(r"^(namespace|struct|class|enum|union|template|extern|using|typedef|#|//)")
NAME = re.compile(r"([A-Za-z_~][A-Za-z_0-9:<>~]*)\s*\(")


def functions(path):
    """(line, name, length) of every namespace-level function definition in `path`."""
    with open(path, encoding="utf-8", errors="replace") as f:
        lines = f.read().split("\n")
    out = []
    i = 0
    while i < len(lines):
        line = lines[i]
        if HEAD_START.match(line) and not NOT_A_FUNCTION.match(line) and "(" in line:
            # The head: this line up to the one ending with '{' (at most a few lines on).
            j = i
            while j < len(lines) and j < i + 12 and not lines[j].rstrip().endswith("{") \
                    and not lines[j].rstrip().endswith(";"):
                j += 1
            if j < len(lines) and lines[j].rstrip().endswith("{") and not lines[j].rstrip().endswith("= {"):
                end = j + 1
                while end < len(lines) and lines[end] != "}" and not lines[end].startswith("}  //"):
                    end += 1
                m = NAME.search(line)
                out.append((i + 1, m.group(1) if m else line.strip(), end - j))
                i = end + 1
                continue
        i += 1
    return out


def check(dirs, limit):
    over = []
    for d in dirs:
        for root, _, files in os.walk(d):
            for name in sorted(files):
                if name.endswith((".cc", ".cpp", ".h")):
                    path = os.path.join(root, name)
                    over += [(path, line, fn, n) for line, fn, n in functions(path) if n > limit]
    return over


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--limit", type=int, default=80)
    ap.add_argument("--plant", action="store_true")
    ap.add_argument("--allow", help="allow-list of the functions still over the limit (may only shrink)")
    ap.add_argument("dirs", nargs="*")
    a = ap.parse_args()
    if a.plant:
        with tempfile.TemporaryDirectory() as t:
            with open(os.path.join(t, "planted.cc"), "w") as f:
                f.write("namespace x {\n\nint planted_long_function(int a,\n                           int b) {\n"
                        + "  ++a;\n" * (a.limit + 1) + "  return a + b;\n}\n\n}  // namespace x\n")
            found = check([t], a.limit)
            if [fn for _, _, fn, _ in found] != ["planted_long_function"]:
                print(f"the planted function was not found: {found}")
                return 1
            planted = os.path.normpath(os.path.join(t, "planted.cc"))
            n = found[0][3]
            # Allowed at its length it passes; allowed shorter, or a stale entry, fails.
            if verdict([t], a.limit, {(planted, "planted_long_function"): n}, "list") \
                    or not verdict([t], a.limit, {(planted, "planted_long_function"): n - 1}, "list") \
                    or not verdict([t], a.limit, {(planted, "planted_long_function"): n,
                                                  (planted, "gone_function"): n}, "list"):
                print("the allow-list is not applied as it should be (planted function)")
                return 1
    messages = verdict(a.dirs, a.limit, read_allow_list(a.allow) if a.allow else {}, a.allow)
    for m in messages:
        print(m)
    return 1 if messages else 0


def verdict(dirs, limit, allowed, allow_name):
    """One line for every function over the limit that the allow-list does not hold, or holds
    shorter, and for every entry left without a function over the limit; empty when all is well."""
    messages = []
    seen = set()
    for path, line, fn, n in check(dirs, limit):
        key = (os.path.normpath(path), fn)
        if key in allowed:
            seen.add(key)
            if n <= allowed[key]:
                continue
            messages.append(f"{path}:{line}: {fn} has {n} lines, more than the {allowed[key]} its entry in "
                            f"{allow_name} allows")
        else:
            messages.append(f"{path}:{line}: {fn} has {n} lines (limit {limit})")
    for key in sorted(set(allowed) - seen):
        messages.append(f"{allow_name}: {key[0]} {key[1]} is no longer over {limit} lines (or is gone): remove its "
                        "entry (the list only shrinks)")
    return messages


def read_allow_list(path):
    """{(path, name): lines} from the allow-list (comments after '#')."""
    out = {}
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            fields = line.split("#", 1)[0].split()
            if not fields:
                continue
            if len(fields) != 3 or not fields[2].isdigit():
                raise SystemExit(f"{path}:{number}: expected 'PATH NAME LINES', got {line.strip()!r}")
            out[(os.path.normpath(fields[0]), fields[1])] = int(fields[2])
    return out


if __name__ == "__main__":
    sys.exit(main())
