"""gmwm.stability (issue 48): the frequency-stability deviations in Python, the command's
document for the same data, Stable32's values for NBS14's 1000-point set, phase input, and the
refusals."""
import json

import numpy as np
import pytest

import gmwm
from cli_support import run


def nbs1000():
    n, y = 1234567890, []
    for _ in range(1000):
        y.append(n / 2147483647)
        n = (16807 * n) % 2147483647
    return np.array(y)


def test_the_deviations_are_stable32s_and_the_commands_for_the_same_data(tmp_path):
    y = nbs1000()
    d = gmwm.stability(y, freq=1.0, kind=["oadev", "mdev"], taus=[1, 10, 99], names=["y"])
    oadev = d.columns[0].deviations["oadev"]
    assert oadev.m.tolist() == [1, 10, 99] and oadev.n.tolist() == [999, 981, 803]
    # Stable32 1.60 on the set's phase, as printed.
    assert oadev.value.tolist() == pytest.approx([2.9223e-01, 9.1600e-02, 3.2616e-02], rel=5e-5)
    assert d.columns[0].deviations["mdev"].value.tolist() == pytest.approx([2.9223e-01, 6.1724e-02, 2.1850e-02],
                                                                           rel=5e-5)
    path = tmp_path / "y.csv"
    path.write_text("time [s],y\n" + "".join(f"{k},{v!r}\n" for k, v in enumerate(y)))
    cli = json.loads(run(tmp_path, "stability", str(path), "--kind", "oadev,mdev", "--taus", "1,10,99",
                         "--json", "-").stdout)
    assert cli["columns"][0]["deviations"] == d.document["columns"][0]["deviations"]
    assert (tuple(cli["kinds"]), cli["taus"], cli["tau0"]) == (d.kinds, list(d.taus), d.tau0)


def test_phase_gives_the_deviations_of_the_frequency_it_integrates_as_the_command_does(tmp_path):
    y = nbs1000()
    x = np.concatenate([[0.0], np.cumsum(y)])
    a = gmwm.stability(y, freq=1.0, kind="adev,hdev,totdev", taus="decade")
    b = gmwm.stability(x, freq=1.0, kind="adev,hdev,totdev", taus="decade", phase=True, names=["x"])
    assert b.data == "phase"
    for kind in ("adev", "hdev", "totdev"):
        assert b.columns[0].deviations[kind].value == pytest.approx(a.columns[0].deviations[kind].value, rel=1e-9)
    # The command on the same phase: the same deviations and the same reading of the rates
    # (held samples looked for in the rates both read, not in the phase).
    path = tmp_path / "x.csv"
    path.write_text("time [s],x\n" + "".join(f"{k},{v!r}\n" for k, v in enumerate(x)))
    cli = json.loads(run(tmp_path, "stability", str(path), "--data", "phase", "--kind", "adev,hdev,totdev",
                         "--taus", "decade", "--json", "-").stdout)
    assert cli["columns"][0]["deviations"] == b.document["columns"][0]["deviations"]
    assert cli.get("repeated_samples") == b.document.get("repeated_samples")


def test_each_deviation_carries_stable32s_interval_and_its_noise_as_the_command_does(tmp_path):
    y = nbs1000()
    d = gmwm.stability(y, freq=1.0, kind="oadev,totdev", names=["y"])
    oadev = d.columns[0].deviations["oadev"]
    # Stable32 1.60's one-sigma ("0.683") interval at tau = 1 s, white FM.
    assert (oadev.ci_low[0], oadev.ci_high[0]) == pytest.approx((2.8515e-01, 2.9987e-01), abs=0.5e-5)
    assert oadev.alpha[0] == 0 and oadev.noise[0] == "white FM" and oadev.noise_id[0] == "acf"
    assert np.all(oadev.ci_low < oadev.value) and np.all(oadev.value < oadev.ci_high)
    assert d.confidence == pytest.approx(0.6827, abs=1e-4) and d.interval_method == "stable32" and d.noise_alpha is None
    fixed = gmwm.stability(y, freq=1.0, kind="oadev", noise_alpha=0, intervals="exact", confidence=0.95)
    f = fixed.columns[0].deviations["oadev"]
    assert set(f.noise_id) == {"fixed"} and set(f.alpha.tolist()) == {0}
    assert fixed.noise_alpha == 0 and fixed.interval_method == "exact" and fixed.confidence == 0.95
    path = tmp_path / "y.csv"
    path.write_text("time [s],y\n" + "".join(f"{k},{v!r}\n" for k, v in enumerate(y)))
    cli = json.loads(run(tmp_path, "stability", str(path), "--kind", "oadev", "--noise-alpha", "0", "--intervals",
                         "exact", "--confidence", "0.95", "--json", "-").stdout)
    assert cli["columns"][0]["deviations"] == fixed.document["columns"][0]["deviations"]
    with pytest.raises(gmwm.InputError, match="^confidence: found 1.5, expected a number between 0 and 1"):
        gmwm.stability(y, freq=1.0, confidence=1.5)
    with pytest.raises(gmwm.InputError, match="^intervals: found 'fast', expected stable32 or exact"):
        gmwm.stability(y, freq=1.0, intervals="fast")


def test_a_bad_kind_tau_or_rate_is_refused_naming_it():
    y = nbs1000()
    with pytest.raises(gmwm.InputError, match="^kind: found 'allan', expected adev, oadev"):
        gmwm.stability(y, freq=1.0, kind="allan")
    with pytest.raises(gmwm.InputError, match="^taus: 2.5 s is not a whole number of sampling periods of 1 s"):
        gmwm.stability(y, freq=1.0, taus=[1, 2.5])
    with pytest.raises(gmwm.InputError, match="taus: found 'weekly', expected all, octave, decade"):
        gmwm.stability(y, freq=1.0, taus="weekly")
    with pytest.raises(gmwm.InputError, match="give the sampling rate with freq"):
        gmwm.stability(y)


def test_the_plot_draws_each_kind_with_its_interval_band_in_its_unit_and_the_table_is_a_dataframe(tmp_path):
    matplotlib = pytest.importorskip("matplotlib", reason="python3-matplotlib (tools/setup.sh installs it)")
    matplotlib.use("Agg")
    y = nbs1000()
    d = gmwm.stability(y, freq=1.0, kind="oadev,mdev,tdev", names=["y"], units="deg/s")
    ax = d.plot()
    labels = [line.get_label() for line in ax.get_lines() if not line.get_label().startswith("_")]
    assert labels == ["oadev", "mdev"]  # tdev is in the phase's unit: plotted on its own
    assert ax.get_xlabel() == "tau [s]" and ax.get_ylabel() == "deviation [deg/s]"
    assert len(ax.collections) == 2  # one band per kind
    tdev = d.plot(kinds=["tdev"])
    assert tdev.get_ylabel() == "deviation [(deg/s)*s]"
    with pytest.raises(ValueError, match="the time deviations .* are in the phase's unit"):
        d.plot(kinds=["oadev", "tdev"])
    with pytest.raises(ValueError, match="'hdev' is not among this column's deviations"):
        d.plot(kinds=["hdev"])
    ax.figure.savefig(tmp_path / "stability.png", dpi=80)
    assert (tmp_path / "stability.png").stat().st_size > 12_000
    pandas = pytest.importorskip("pandas")
    frame = d.columns[0].to_dataframe()
    assert isinstance(frame, pandas.DataFrame)
    assert set(frame["kind"]) == {"oadev", "mdev", "tdev"}
    first = frame[(frame.kind == "oadev") & (frame.m == 1)].iloc[0]
    assert (first.ci_low, first.ci_high) == pytest.approx((2.8515e-01, 2.9987e-01), abs=0.5e-5)
    assert first.noise == "white FM" and first.unit == "deg/s"


def three_sensors(levels, n=20000, seed=11):
    """Three sensors at 100 Hz: white rate noise of 1e-3 times `levels` each under a common input
    (white 0.3, a random walk, a slow sine: a platform's rotation) a hundred times larger."""
    rng = np.random.default_rng(seed)
    t = np.arange(n)
    common = 0.3 * rng.normal(size=n) + np.cumsum(3e-4 * rng.normal(size=n)) + 0.5 * np.sin(2 * np.pi * t / 6000)
    return np.stack([common + 1e-3 * s * rng.normal(size=n) for s in levels], axis=1)


def test_the_hat_separates_three_columns_from_their_common_input_as_the_command_does(tmp_path):
    x = three_sensors([1.0, 2.0, 3.0])
    d = gmwm.stability(x, freq=100.0, kind="oadev,mdev", hat=True, names=["a", "b", "c"], units="rad/s")
    hat = d.hat
    assert hat.sensors == ("a", "b", "c") and [p.name for p in hat.pairs] == ["a - b", "b - c", "c - a"]
    assert d.columns[0].deviations["oadev"].value[0] > 0.29  # each column alone: the common input
    for kind in ("oadev", "mdev"):
        k = hat.deviations[kind]
        assert k.unit == "rad/s" and k.m.tolist() == hat.pairs[0].deviations[kind].m.tolist()
        for s, sensor in enumerate(k.sensors):
            # At 0.01 s (15650 degrees of freedom) each within 9% / 3% / 3% of its level.
            assert sensor.value[0] == pytest.approx(1e-3 * (s + 1), rel=0.09 if s == 0 else 0.03)
            assert sensor.ci_low[0] < sensor.value[0] < sensor.ci_high[0]
            assert np.all(np.isnan(sensor.value[sensor.negative]))
            assert np.all(sensor.variance[sensor.negative] < 0)
    assert gmwm.stability(x, freq=100.0).hat is None
    path = tmp_path / "three.csv"
    path.write_text("a,b,c\n" + "".join(f"{r[0]!r},{r[1]!r},{r[2]!r}\n" for r in x))
    cli = json.loads(run(tmp_path, "stability", str(path), "--freq", "100", "--hat", "--kind", "oadev,mdev", "--units",
                         "rad/s", "--json", "-").stdout)
    assert cli["hat"] == d.document["hat"]
    from test_every_key_typed import untyped_keys  # every key of the hat typed (issue 45's walk)
    assert untyped_keys(d, d.document, "stability") == []


def test_the_hat_flags_a_negative_variance_and_reads_only_three_columns():
    x = three_sensors([0.0, 2.0, 3.0], seed=1)  # a is the common input alone: its deviation is 0
    a = gmwm.stability(x, freq=100.0, hat=True).hat.deviations["oadev"].sensors[0]
    assert a.negative.sum() >= 3
    assert np.all(np.isnan(a.value[a.negative])) and np.all(a.variance[a.negative] < 0)
    with pytest.raises(gmwm.InputError, match=r"^<array>: hat=True: the three-cornered hat reads three columns recorded together "
                                              r"\(columns A,B,C\), found 2 \(x1, x2\)"):
        gmwm.stability(x[:, :2], freq=100.0, hat=True)
    with pytest.raises(gmwm.InputError, match="^hat=True: mtie is a maximum, not a variance"):
        gmwm.stability(x, freq=100.0, kind="oadev,mtie", hat=True)
