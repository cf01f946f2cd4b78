"""Every Python refusal names a Python keyword, never a command-line option (issue 46: some
errors said --freq where the caller wrote freq=). One bad value for each keyword a user
types, across every function: each raises gmwm.InputError whose one line names the keyword
and holds no "--"."""
import pytest

import gmwm

TRUTH = "WN(sigma2=1e-4)+RW(gamma2=1e-9)"
CURVE = {"tau": [0.01, 0.02, 0.04], "value": [1.0, 0.5, 0.25]}  # a curve whose values say no quantity


@pytest.fixture(scope="module")
def x():
    return gmwm.simulate(TRUTH, 4096, seed=5, freq=100)


@pytest.fixture(scope="module")
def fit_result(x):
    return gmwm.fit(x, "WN+RW", freq=100, units="rad/s", name="gyro_x")


CASES = [
    ("wv freq", lambda x, f: gmwm.wv(x, freq=0), "freq"),
    ("wv no freq", lambda x, f: gmwm.wv(x), "freq"),
    ("wv alpha", lambda x, f: gmwm.wv(x, freq=100, alpha=2), "alpha"),
    ("wv levels", lambda x, f: gmwm.wv(x, freq=100, levels=40), "levels"),
    ("wv estimator", lambda x, f: gmwm.wv(x, freq=100, robust=True, estimator="tukey"), "estimator"),
    ("wv eff", lambda x, f: gmwm.wv(x, freq=100, robust=True, eff=1.5), "eff"),
    ("wv spike_screen", lambda x, f: gmwm.wv(x, freq=100, spike_screen=False), "spike_screen"),
    ("wv adev_points", lambda x, f: gmwm.wv(x, freq=100, adev=True, adev_points=0), "adev_points"),
    ("allan points_per_octave", lambda x, f: gmwm.allan(x, freq=100, points_per_octave=0), "points_per_octave"),
    ("allan units", lambda x, f: gmwm.allan(x, freq=100, units="furlong"), "units"),
    ("fit model", lambda x, f: gmwm.fit(x, "WN+ZZ", freq=100), "model"),
    ("fit omega", lambda x, f: gmwm.fit(x, "WN", freq=100, omega="nope"), "omega"),
    ("fit kf_rate", lambda x, f: gmwm.fit(x, "WN", freq=100, kf_rate=-1), "kf_rate"),
    ("fit max_evaluations", lambda x, f: gmwm.fit(x, "WN", freq=100, max_evaluations=1), "max_evaluations"),
    ("select optimism", lambda x, f: gmwm.select(x, "WN+RW", freq=100, optimism="nope"), "optimism"),
    ("select penalty", lambda x, f: gmwm.select(x, "WN+RW", freq=100, penalty="aic"), "penalty"),
    ("select models", lambda x, f: gmwm.select(x, freq=100, models="WN;;RW"), "models"),
    ("select names", lambda x, f: gmwm.select(x, "WN", freq=100, names=["a", "b"]), "names"),
    ("gap baseline", lambda x, f: gmwm.gap(x, freq=100), "model"),
    ("gap sensor", lambda x, f: gmwm.gap(x, freq=100, model=TRUTH, sensor="mag"), "sensor"),
    ("gap levels", lambda x, f: gmwm.gap(x, freq=100, model=TRUTH, levels=40), "levels"),
    ("fit_joint optimism", lambda x, f: gmwm.select_joint([x, x * 1.1], "WN", freq=100, optimism="nope"),
     "optimism"),
    ("plan unit", lambda x, f: gmwm.plan(model=TRUTH, freq=100, unit="furlong"), "unit"),
    ("export format", lambda x, f: gmwm.export(f, format="nope"), "format"),
    ("export sensor", lambda x, f: gmwm.export(f, format="kalibr", sensor="mag"), "sensor"),
    ("export inflate", lambda x, f: gmwm.export(f, format="kalibr", sensor="gyro", partial=True, inflate=-1), "inflate"),
    ("export partial", lambda x, f: gmwm.export(f, format="kalibr", sensor="gyro"), "partial"),
    ("export consistent_for count", lambda x, f: gmwm.export(f, format="kalibr", consistent_for=(20,)),
     "consistent_for"),
    ("export consistent_for sign", lambda x, f: gmwm.export(f, format="kalibr", consistent_for=(20, -60)),
     "consistent_for"),
    ("plan result list", lambda x, f: gmwm.plan("[" + f.to_json() + "]"), "result"),
    ("plan result type", lambda x, f: gmwm.plan(3.5), "result"),
    ("nav trajectory", lambda x, f: gmwm.nav("missing.json", ["truth"], trajectory="loop"), "trajectory"),
    ("read columns", lambda x, f: gmwm.read("data/example_imu6.csv.gz", columns=["nope"]), "columns"),
    ("read memory", lambda x, f: gmwm.read("data/example_imu6.csv.gz", memory=0), "memory"),
    ("fleet memory", lambda x, f: gmwm.fleet("fleet.csv", model="WN", memory=0), "memory"),
    ("fit_curve value", lambda x, f: gmwm.fit_curve(CURVE, "WN"), "value"),
    ("fit_curve freq", lambda x, f: gmwm.fit_curve(CURVE, "WN", value="avar", freq=10), "freq"),
    ("fit_curve record", lambda x, f: gmwm.fit_curve(CURVE, "WN", value="avar", record=0.01), "record"),
    ("fit_curve exclude_taus", lambda x, f: gmwm.fit_curve(CURVE, "WN", value="avar", exclude_taus="2:1"),
     "exclude_taus"),
    ("fit_curve confidence", lambda x, f: gmwm.fit_curve(CURVE, "WN", value="avar", confidence=1.5), "confidence"),
]


@pytest.mark.parametrize("name,call,keyword", CASES, ids=[c[0] for c in CASES])
def test_the_refusal_names_the_python_keyword_and_no_command_line_option(x, fit_result, name, call, keyword,
                                                                           monkeypatch):
    from cli_support import SOURCE

    monkeypatch.chdir(SOURCE)
    with pytest.raises(gmwm.InputError) as e:
        call(x, fit_result)
    said = str(e.value)
    assert keyword in said, f"{name}: {said}"
    assert "--" not in said and "\n" not in said, f"{name}: {said}"
