"""The module's joint fit, joint selection and export against the command line: the same
recordings (replicates) and options give the command's JSON to the last bit, the sources
named "replicates[k]" where the command names the files; and their refusals."""
import json
import os
import subprocess

import numpy as np
import pytest

import gmwm

SOURCE = os.environ.get("GMWM_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
CLI = os.path.abspath(os.environ.get("GMWM_CLI_PATH", os.path.join(SOURCE, "build", "gmwm")))
TRUTH = "AR1(phi=0.999,sigma2=1e-8)+WN(sigma2=1e-5)+RW(gamma2=1e-11)"
FILES = ["day1.csv", "day2.csv", "day3.csv"]


def run(cwd, *args):
    done = subprocess.run([CLI, *args, "--quiet"], cwd=cwd, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr


def cli_document(folder, name):
    doc = json.loads((folder / name).read_text())
    doc.pop("run")
    return doc


def as_arrays(doc):
    """The command's document with its file names as the module names arrays."""
    text = json.dumps(doc)
    for k, f in enumerate(FILES):
        text = text.replace(f'"{f}:', f'"replicates[{k}]:').replace(f'"{f}"', f'"replicates[{k}]"')
    return json.loads(text)


@pytest.fixture(scope="module")
def recordings(tmp_path_factory):
    """Three recordings of a two-axis gyroscope (simulated by the command) and their columns."""
    folder = tmp_path_factory.mktemp("replicates")
    arrays = []
    for k, f in enumerate(FILES):
        run(folder, "simulate", "--model", TRUTH, "--n", "16384", "--freq", "100", "--signals", "2", "--names",
            "gyro_x,gyro_y", "--seed", str(k + 1), "--output", f)
        arrays.append(np.loadtxt(folder / f, delimiter=",", skiprows=1)[:, 1:])
    return folder, arrays


def test_fit_joint_equals_the_clis_joint_fit_bit_for_bit(recordings):
    folder, arrays = recordings
    run(folder, "fit", FILES[0], "--joint", FILES[1], FILES[2], "--model", "AR1+WN+RW", "--freq", "100", "--units",
        "gyro=rad/s", "--json", "fj.json")
    mine = gmwm.fit_joint(arrays, "AR1+WN+RW", freq=100, names=["gyro_x", "gyro_y"], units="gyro=rad/s")
    assert json.loads(mine.to_json()) == as_arrays(cli_document(folder, "fj.json"))
    assert isinstance(mine, gmwm.JointFitResult)
    assert [c.name for c in mine.columns] == ["gyro_x", "gyro_y"]
    assert mine.columns[0].replicate_test is not None


def test_select_joint_equals_the_clis_joint_selection_bit_for_bit_with_effective_models(recordings):
    folder, arrays = recordings
    run(folder, "select", FILES[0], "--joint", FILES[1], FILES[2], "--model", "2*AR1+WN+RW", "--freq", "100",
        "--columns", "gyro_x", "--json", "sj.json")
    mine = gmwm.select_joint([a[:, :1] for a in arrays], "2*AR1+WN+RW", freq=100, names=["gyro_x"])
    assert json.loads(mine.to_json()) == as_arrays(cli_document(folder, "sj.json"))
    ranking = mine.columns[0].ranking
    assert len(ranking) == 3 * 2 * 2 - 1  # every sub-model of 2*AR1+WN+RW: 0-2 AR1, WN or not, RW or not
    # Every candidate names the effective model it fell onto, itself when nothing reduced.
    assert all(r.effective for r in ranking)
    assert len({r.effective for r in ranking}) < len(ranking)


def test_export_equals_the_clis_export_file_and_document(recordings, tmp_path, monkeypatch):
    folder, arrays = recordings
    monkeypatch.chdir(folder)  # the result named as the command names it: fit.json
    run(folder, "fit", FILES[0], "--model", "AR1+WN+RW", "--units", "gyro=rad/s", "--json", "fit.json")
    for fmt, extra in (("kalibr", []), ("basalt", ["--aggregate", "worst"])):
        out = tmp_path / f"out_{fmt}"
        run(folder, "export", "fit.json", "--format", fmt, "--output", str(out), "--json", str(tmp_path / "e.json"),
            "--partial", *extra)
        options = {"aggregate": "worst", "partial": True} if extra else {"partial": True}
        mine = gmwm.export("fit.json", format=fmt, output=str(out), **options)
        assert json.loads(mine.to_json()) == cli_document(tmp_path, "e.json")
        assert mine.content == out.read_text()
        sidecar = tmp_path / f"out_{fmt}.txt"
        assert mine.sidecar_content == (sidecar.read_text() if sidecar.exists() else None)


def test_export_takes_a_typed_fit_and_derives_a_consistent_inflation(recordings):
    _, arrays = recordings
    f = gmwm.fit(arrays[0][:, 0], "WN+RW", freq=100, units="rad/s", name="gyro_x")
    # A gyroscope's model alone: refused for a file with accelerometer fields (a 0 would read as
    # a perfect accelerometer), written with partial=True (the accelerometer's fields left out).
    with pytest.raises(gmwm.InputError, match="no accelerometer column in the source"):
        gmwm.export(f, format="kalibr")
    e = gmwm.export(f, format="kalibr", partial=True)
    assert "gyroscope_noise_density" in e.content
    assert "accelerometer_noise_density" not in e.content
    assert e.written["gyro"].combined.noise_density == pytest.approx(f.noise_figures.N.value, rel=1e-12)
    with pytest.raises(gmwm.InputError, match="needs the models of both sensors"):
        gmwm.export(f, format="kalibr", consistent_for=(20.0, 60.0, 0.05), partial=True)
    with pytest.raises(gmwm.InputError, match="consistent_for derives the inflation; leave out inflate"):
        gmwm.export(f, format="kalibr", inflate=2.0, consistent_for=(20.0, 60.0, 0.05), partial=True)


def test_replicates_that_do_not_match_are_refused_naming_the_recording(recordings):
    _, arrays = recordings
    with pytest.raises(gmwm.InputError, match=r"replicates\[1\]: has 1 columns, expected 2"):
        gmwm.fit_joint([arrays[0], arrays[1][:, 0]], "WN+RW", freq=100)
    with pytest.raises(gmwm.InputError, match=r"replicates\[1\]: replicates\[1\]:x1 is the same recording"):
        gmwm.fit_joint([arrays[0][:, 0], arrays[0][:, 0]], "WN+RW", freq=100)
    with pytest.raises(gmwm.InputError, match="at least 2 recordings"):
        gmwm.fit_joint([arrays[0]], "WN+RW", freq=100)
    with pytest.raises(gmwm.InputError, match=r"^optimism: found 'bootstrap', expected replicates or all$"):
        gmwm.select_joint(arrays, "WN+RW", freq=100, optimism="bootstrap")
    with pytest.raises(gmwm.InputError, match="expected a gmwm.FitResult"):
        gmwm.export(42, format="kalibr")
