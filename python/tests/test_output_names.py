"""Column names from a file reach the CLI's CSV, JSON and HTML outputs as data, never as their
syntax (issue 25), read back with real parsers: Python's csv, json and html.parser."""
import csv
import io
import json
import math
import os
import subprocess
from html.parser import HTMLParser

import pytest

SOURCE = os.environ.get("GMWM_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
CLI = os.path.abspath(os.environ.get("GMWM_CLI_PATH", os.path.join(SOURCE, "build", "gmwm")))

HOSTILE = [
    "gyro\x1b[2J\x1b]0;pwned\x07x",
    '=HYPERLINK("http://evil";"click")+0',
    "</script><script>alert(1)</script>",
    "a\"quoted\";name",
]
PLAIN = ["a", "b", "c", "d"]


def write_csv(path, names):
    def cell(name):
        return '"' + name.replace('"', '""') + '"'

    lines = ["time," + ",".join(cell(n) for n in names)]
    for i in range(4096):
        values = [math.sin(i * 0.37), math.cos(i * 0.1), math.sin(i * 0.05) + (i % 3) * 0.01, math.sin(i * 1.3)]
        lines.append("%.2f," % (i * 0.01) + ",".join("%.9f" % v for v in values))
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


class Tags(HTMLParser):
    def __init__(self):
        super().__init__()
        self.tags, self.text = [], []

    def handle_starttag(self, tag, attrs):
        self.tags.append(tag)

    def handle_data(self, data):
        self.text.append(data)


def run(tmp_path, names, report):
    write_csv(tmp_path / "in.csv", names)
    args = [CLI, "wv", str(tmp_path / "in.csv"), "--csv", str(tmp_path / "wv.csv"), "--json", str(tmp_path / "wv.json"),
            "--quiet"]
    if report:
        args += ["--report", str(tmp_path / "r.html")]
    done = subprocess.run(args, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr


def report_possible(tmp_path):
    write_csv(tmp_path / "probe.csv", PLAIN)
    done = subprocess.run([CLI, "wv", str(tmp_path / "probe.csv"), "--report", str(tmp_path / "probe.html"), "--quiet"],
                          capture_output=True, text=True)
    return done.returncode == 0


def test_csv_and_json_read_back_the_names_as_data(tmp_path):
    run(tmp_path, HOSTILE, report=False)
    rows = list(csv.reader(io.StringIO((tmp_path / "wv.csv").read_text(encoding="utf-8"))))
    header, body = rows[0], rows[1:]
    assert all(len(r) == len(header) for r in body)
    names = []
    for r in body:
        if r[0] not in names:
            names.append(r[0])
    # Each name is one cell; a formula is disarmed by a leading quote.
    assert names == [HOSTILE[0], "'" + HOSTILE[1], HOSTILE[2], HOSTILE[3]]
    doc = json.loads((tmp_path / "wv.json").read_text(encoding="utf-8"))
    assert [c["name"] for c in doc["columns"]] == HOSTILE


def test_the_report_has_the_structure_of_a_plain_named_one(tmp_path):
    if not report_possible(tmp_path):
        pytest.skip("no HTML report on this machine (Vega missing)")
    plain_dir, hostile_dir = tmp_path / "plain", tmp_path / "hostile"
    plain_dir.mkdir()
    hostile_dir.mkdir()
    run(plain_dir, PLAIN, report=True)
    run(hostile_dir, HOSTILE, report=True)
    plain, hostile = Tags(), Tags()
    plain.feed((plain_dir / "r.html").read_text(encoding="utf-8"))
    hostile.feed((hostile_dir / "r.html").read_text(encoding="utf-8"))
    assert hostile.tags == plain.tags
    assert any(HOSTILE[2] in t for t in hostile.text)
    assert not any("\x1b" in t for t in hostile.text)
