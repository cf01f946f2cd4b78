"""examples/gmwm_tour.ipynb runs in the suite (issue 46, item 4): executed by Debian's
nbconvert on the shipped example and on a real ADIS16405 recording, its outputs checked
against the gmwm command's on the same data (selection, Kalibr file, consistent inflation,
recording plan) and its plots present as PNG images."""

from __future__ import annotations

import base64
import json
import os
import re
import subprocess
import sys
from pathlib import Path
from typing import Any, Dict, List

import pytest

nbformat = pytest.importorskip("nbformat", reason="python3-nbformat is not installed (tools/setup.sh installs it)")
pytest.importorskip("nbconvert", reason="python3-nbconvert is not installed (tools/setup.sh installs it)")

SOURCE = Path(os.environ.get("GMWM_SOURCE_DIR", Path(__file__).resolve().parents[2]))
NOTEBOOK = SOURCE / "examples" / "gmwm_tour.ipynb"
EXAMPLE = SOURCE / "data" / "example_imu6.csv.gz"
CLI = os.environ.get("GMWM_CLI_PATH")
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def shared_recording(name: str) -> Path:
    """A real recording from GMWM_SHARED_DATA: skipped when absent, a failure when
    GMWM_REQUIRE_SHARED_DATA=1 (as .ci/run sets)."""
    folder = os.environ.get("GMWM_SHARED_DATA", "")
    path = Path(folder) / name
    if not folder or not path.is_file():
        why = f"the real recordings are absent (GMWM_SHARED_DATA={folder!r} holds no {name})"
        if os.environ.get("GMWM_REQUIRE_SHARED_DATA") == "1":
            pytest.fail(why + " and GMWM_REQUIRE_SHARED_DATA=1")
        pytest.skip(why)
    return path


def execute(tmp_path: Path, recording: Path | None) -> Any:
    env = dict(os.environ)
    env.pop("GMWM_RECORDING", None)
    # The kernel runs in examples/: the suite's package path, made absolute.
    if env.get("PYTHONPATH"):
        env["PYTHONPATH"] = os.pathsep.join(os.path.abspath(p) for p in env["PYTHONPATH"].split(os.pathsep) if p)
    if recording is not None:
        env["GMWM_RECORDING"] = str(recording)
    done = subprocess.run([sys.executable, "-m", "nbconvert", "--to", "notebook", "--execute",
                           "--ExecutePreprocessor.timeout=600", "--ExecutePreprocessor.kernel_name=python3",
                           "--output-dir", str(tmp_path), "--output", "executed", str(NOTEBOOK)],
                          env=env, capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, f"nbconvert --execute failed:\n{done.stderr[-4000:]}"
    return nbformat.read(tmp_path / "executed.ipynb", as_version=4)


def code_cells(nb: Any) -> List[Any]:
    return [c for c in nb.cells if c.cell_type == "code"]


def text_of(cell: Any) -> str:
    return "".join(o.get("text", "") for o in cell.outputs if o.output_type == "stream")


def images_of(cell: Any) -> List[bytes]:
    return [base64.b64decode(o["data"]["image/png"]) for o in cell.outputs
            if o.output_type in ("display_data", "execute_result") and "image/png" in o.get("data", {})]


def cli(*args: str, cwd: Path) -> str:
    assert CLI, "GMWM_CLI_PATH names the gmwm program"
    done = subprocess.run([CLI, *args], cwd=cwd, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    return done.stdout


def settings(kalibr_text: str) -> List[str]:
    return [line for line in kalibr_text.splitlines() if line.startswith(("gyroscope_", "accelerometer_"))]


def check_against_the_command(nb: Any, recording: Path, units: str, tmp_path: Path) -> None:
    cells = code_cells(nb)
    assert len(cells) == 6
    for cell in cells:
        assert cell.outputs, "every cell shows something"
        assert not [o for o in cell.outputs if o.output_type == "error"], text_of(cell)
    read, curves, select, kalibr, safe, plan = (text_of(c) for c in cells)
    n = int(re.search(r"(\d+) samples x 6 columns", read).group(1))  # type: ignore[union-attr]

    # The plots: the WV and the Allan deviation side by side, the selection's figure.
    for k in (1, 2):
        (png,) = images_of(cells[k])
        assert png.startswith(PNG_MAGIC) and len(png) > 20_000, "a drawn figure, not an empty canvas"
    allan = json.loads(cli("wv", str(recording), "--freq", "100", "--columns", "gyro_x", "--adev", "--units", units,
                           "--quiet", "--json", "-", cwd=tmp_path))
    figures = allan["columns"][0]["noise_figures"]
    assert f"N={float(figures['white']['value']):.4g}" in curves

    # The selection: each axis's best model is the command's.
    sel = tmp_path / "select.json"
    cli("select", str(recording), "--freq", "100", "--model", "AR1+WN+RW+QN",
        "--units", units, "--quiet", "--json", str(sel), cwd=tmp_path)
    for column in json.loads(sel.read_text())["columns"]:
        assert f"{column['name']}: best {column['best']} " in select
        assert column["best_model"] in select

    # Kalibr's settings, plain and inflated for a 20 Hz update over 60 s: the command's lines.
    cli("export", str(sel), "--format", "kalibr", "--output", str(tmp_path / "k.yaml"), cwd=tmp_path)
    assert settings((tmp_path / "k.yaml").read_text()) == settings(kalibr) and len(settings(kalibr)) == 4
    cli("export", str(sel), "--format", "kalibr", "--consistent-for", "20,60",
        "--output", str(tmp_path / "safe.yaml"), cwd=tmp_path)
    assert settings((tmp_path / "safe.yaml").read_text()) == settings(safe)
    # The search's aim: a filter that is not optimistic with the inflated figures.
    verdict = re.search(r"inflation: N x[0-9.]+, K x[0-9.]+: (\w+)", safe)
    assert verdict and verdict.group(1) != "optimistic", safe

    # The plan: every target's hours as the command computes them.
    planned = json.loads(cli("plan", str(sel), "--columns", "gyro_x,gyro_y,gyro_z", "--quiet", "--json", "-",
                             cwd=tmp_path))
    assert f"this record: {n / 100 / 3600:.2f} h" in plan
    for column in planned["columns"]:
        for t in column["targets"]:
            shown = f"{t['name']} {t['seconds'] / 3600:.3g} h" if t["reachable"] else f"{t['name']} unreachable"
            assert shown in plan, (shown, plan)


def test_the_notebook_runs_on_the_shipped_example_and_agrees_with_the_command(tmp_path: Path) -> None:
    nb = execute(tmp_path, None)
    assert "example_imu6.csv.gz: 65536 samples" in text_of(code_cells(nb)[0])
    check_against_the_command(nb, EXAMPLE, "gyro=rad/s,accel=m/s^2", tmp_path)


def test_the_notebook_runs_on_a_real_adis16405_recording_and_agrees_with_the_command(tmp_path: Path) -> None:
    recording = shared_recording("adis_16405_imu1.csv.gz")
    nb = execute(tmp_path, recording)
    assert "adis_16405_imu1.csv.gz: 1000000 samples" in text_of(code_cells(nb)[0])
    check_against_the_command(nb, recording, "gyro=deg/s,accel=g", tmp_path)
