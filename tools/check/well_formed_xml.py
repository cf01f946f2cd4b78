#!/usr/bin/env python3
"""Every shipped XML file (*.sdf, *.xml, *.urdf, *.world) in the given folders is well-formed
XML 1.0, read by a strict parser (Python's xml.etree, expat): a simulator or a user's tool
that parses the examples strictly must not refuse them. tinyxml2, which gmwm's own reader
uses, is lenient (it reads "--" inside a comment, which XML 1.0 section 2.5 forbids), so
gmwm's tests alone do not catch it (issue 43, item 6: data/adis16405_gz.sdf had
"`gmwm gap --gazebo`" in its comment and Python refused it).

    well_formed_xml.py [--plant] DIR_OR_FILE ...

Prints every file that does not parse as FILE:LINE:COLUMN: REASON and exits 1; exits 0
when all parse (and at least one file was checked). --plant checks the checker: a planted
comment holding "--" in a temporary file must be refused.
"""
import argparse
import os
import sys
import tempfile
import xml.etree.ElementTree as ET

EXTENSIONS = (".sdf", ".xml", ".urdf", ".world")


def files(paths):
    """The XML files named or found (not recursively: data/ is flat) under `paths`, sorted."""
    out = []
    for p in paths:
        if os.path.isdir(p):
            out += [os.path.join(p, n) for n in sorted(os.listdir(p)) if n.lower().endswith(EXTENSIONS)]
        else:
            out.append(p)
    return out


def problem(path):
    """None when `path` is well-formed XML, else 'LINE:COLUMN: reason'."""
    try:
        ET.parse(path)
        return None
    except ET.ParseError as e:
        line, column = e.position
        return f"{line}:{column}: {e}"


def plant():
    """True when a comment holding '--' is refused (the checker works)."""
    with tempfile.NamedTemporaryFile("w", suffix=".sdf", delete=False) as f:
        f.write('<?xml version="1.0"?>\n<!-- see gmwm gap --gazebo -->\n<sdf version="1.9"/>\n')
    try:
        return problem(f.name) is not None
    finally:
        os.unlink(f.name)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--plant", action="store_true", help="check that a planted malformed file is refused")
    parser.add_argument("paths", nargs="+")
    args = parser.parse_args()
    if args.plant and not plant():
        print("the checker accepted a comment holding '--': it checks nothing")
        return 1
    checked = files(args.paths)
    if not checked:
        print("no XML file found in " + ", ".join(args.paths))
        return 1
    bad = 0
    for path in checked:
        why = problem(path)
        if why:
            print(f"{path}:{why}")
            bad += 1
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
