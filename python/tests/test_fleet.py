"""gmwm.fleet against `gmwm fleet`: the same manifest gives the command's JSON to the last
bit, typed rows; the manifest's bad rows are refused with one line each."""
import json
import os

import numpy as np
import pytest

import gmwm

from cli_support import run, write_fleet

TRUTH = "WN(sigma2=1e-4)+RW(gamma2=1e-10)"


@pytest.fixture(scope="module")
def fleet_dir(tmp_path_factory):
    folder = tmp_path_factory.mktemp("fleet")
    write_fleet(folder, 5, TRUTH, 3, "WN(sigma2=4e-4)+RW(gamma2=1e-10)")
    return folder


def test_fleet_equals_the_clis_fleet_document_bit_for_bit_with_typed_rows(fleet_dir, monkeypatch):
    run(fleet_dir, "fleet", "fleet.csv", "--model", "WN+RW", "--json", "fleet.json", "--quiet")
    cli = json.loads((fleet_dir / "fleet.json").read_text())
    cli.pop("run")
    monkeypatch.chdir(fleet_dir)  # the manifest named as the command names it
    mine = gmwm.fleet("fleet.csv", model="WN+RW")
    doc = json.loads(mine.to_json())
    # The second run takes the first's records from the cache: the rows' wall times are the
    # first run's, only the cache flags differ.
    assert doc["cached"] == 5 and cli["cached"] == 0
    for d in (cli, doc):
        d.pop("cached")
        for r in d["rows"]:
            r.pop("cached")
    assert doc == cli
    assert isinstance(mine, gmwm.FleetResult)
    assert len(mine.rows) == 10 and mine.failed == 0
    assert {r.first_level for r in mine.rows} == {1}  # auto: nothing repeats in these units
    row = mine.rows[0]
    assert (row.unit, row.axis, row.unit_of_data, row.status) == ("SN1", "gyro_x", "rad/s", "ok")
    assert row.N.value == cli["rows"][0]["N"]["value"]
    assert row.N.low < row.N.value < row.N.high
    flagged = {r.unit for r in mine.rows if r.flags}
    assert flagged == {"SN3"}, [r.flags for r in mine.rows]
    summary_n = [s for s in mine.summary if s.figure == "N" and s.axis == "gyro_x"][0]
    assert summary_n.units == 5 and summary_n.flagged == ("SN3",)
    assert summary_n.median == pytest.approx(np.sqrt(1e-4 / 100), rel=0.02)


def test_fleet_to_dataframe_has_a_row_per_unit_and_axis_when_pandas_is_there(fleet_dir, monkeypatch):
    pytest.importorskip("pandas", reason="python3-pandas is not installed: to_dataframe() needs it")
    monkeypatch.chdir(fleet_dir)
    frame = gmwm.fleet("fleet.csv", model="WN+RW").to_dataframe()
    assert list(frame["unit"]) == [f"SN{k}" for k in range(1, 6) for _ in range(2)]
    assert {"N", "N_low", "N_high", "K", "B", "flags"} <= set(frame.columns)


def test_fleet_refuses_the_manifests_bad_rows_with_the_clis_lines(fleet_dir):
    bad = fleet_dir / "bad.csv"
    bad.write_text("path,unit,model\nu1.csv,SN1,IMU-X\nmissing.csv,SN2,IMU-X\nu2.csv,SN1,IMU-X\n")
    cli = run(fleet_dir, "fleet", "bad.csv", "--model", "WN+RW", check=False)
    assert cli.returncode == 2
    with pytest.raises(gmwm.InputError) as e:
        gmwm.fleet(str(bad), model="WN+RW")
    lines = str(e.value).split("\n")
    assert len(lines) == 2
    assert lines[0].startswith(str(bad) + ":3: ") and "missing.csv" in lines[0]
    assert lines[1] == str(bad) + ":4: unit 'SN1' given twice (first at row 2)"
    # The command says the same, a line each (its paths relative to where it ran).
    assert "bad.csv:4: unit 'SN1' given twice (first at row 2)" in cli.stderr


def test_fleet_checks_the_units_against_a_spec_with_typed_verdicts(fleet_dir, monkeypatch):
    monkeypatch.chdir(fleet_dir)
    (fleet_dir / "spec.yaml").write_text("IMU-X:\n  gyroscope:\n    angle_random_walk: 5 deg/sqrt(h)\n")
    t = gmwm.fleet("fleet.csv", model="WN+RW", spec="spec.yaml")
    assert t.spec == "spec.yaml"
    verdicts = {(r.unit, r.axis): r.spec_verdict for r in t.rows}
    # SN3 has 4x the white-noise variance: N 6.9 deg/sqrt(h) against the limit 5; the others 3.4.
    assert {k for k, v in verdicts.items() if v == "fail (N)"} == {("SN3", "gyro_x"), ("SN3", "gyro_y")}
    check = t.rows[0].spec[0]
    assert isinstance(check, gmwm.FleetSpecCheck)
    assert (check.figure, check.limit, check.limit_unit, check.verdict) == ("N", 5.0, "deg/sqrt(h)", "pass")
    assert check.value == pytest.approx(1e-2 / 10 * 180 / np.pi * 60, rel=0.05)
    n_summary = [s for s in t.summary if s.figure == "N" and s.axis == "gyro_x"][0]
    assert n_summary.out_of_spec == ("SN3",) and n_summary.unit == "rad/s"


def test_fleet_diagnoses_each_units_gap_against_a_datasheet_as_gap_does(fleet_dir, monkeypatch):
    monkeypatch.chdir(fleet_dir)
    (fleet_dir / "sheet.yaml").write_text(
        "gyroscope:\n  noise_density: 0.001 rad/s/sqrt(Hz)\n  rate_random_walk: 0.0001 rad/s^2/sqrt(Hz)\n")
    t = gmwm.fleet("fleet.csv", model="WN+RW", gap_datasheet="sheet.yaml", gap_replicates=40, cache=None)
    assert t.gap_baseline == "sheet.yaml"
    assert all(r.gap_verdict in ("none", "closed", "remains") for r in t.rows)
    # SN3's white noise is twice the datasheet's: a gap at the fine scales.
    sn3 = [r for r in t.rows if r.unit == "SN3"]
    assert all(r.gap_verdict != "none" and r.gap_p_value < 0.05 for r in sn3), [r.gap_headline for r in sn3]
    gap = run(fleet_dir, "gap", "u3.csv", "--datasheet", "sheet.yaml", "--replicates", "40", "--json", "-")
    assert json.loads(gap.stdout)["columns"][0]["headline"] == sn3[0].gap_headline
    with pytest.raises(gmwm.InputError, match="give one gap baseline"):
        gmwm.fleet("fleet.csv", model="WN+RW", gap_datasheet="sheet.yaml", gap_kalibr="sheet.yaml")


def test_fleet_joint_gives_each_groups_axis_its_typical_units_model_typed(fleet_dir, monkeypatch):
    monkeypatch.chdir(fleet_dir)
    t = gmwm.fleet("fleet.csv", model="WN+RW", joint=True, joint_draws=39, cache=None)
    assert len(t.joint) == 2
    for j in t.joint:
        assert isinstance(j, gmwm.FleetJointModel)
        # SN3 stands out on N: left out of the typical unit's model.
        assert (j.status, j.units, j.left_out, j.calibration) == ("ok", 4, ("SN3",), "bootstrap"), j
        assert j.N.value == pytest.approx(1e-3, rel=0.03)
        assert isinstance(j.shared, bool) and 0.0 < j.heterogeneity_p <= 1.0


@pytest.mark.parametrize("bad, shown", [(0, "0"), ("x", "'x'"), (True, "True")])
def test_fleet_refuses_a_first_level_it_cannot_take_with_the_commands_words(fleet_dir, bad, shown):
    with pytest.raises(gmwm.InputError) as e:
        gmwm.fleet(fleet_dir / "fleet.csv", model="WN+RW", cache=None, first_level=bad)
    assert str(e.value) == f"first_level: found {shown}, expected auto or a whole number from 1 to 62"
