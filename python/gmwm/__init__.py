"""gmwm: the Generalized Method of Wavelet Moments for inertial sensor noise.

The functions take numpy arrays and return the plain-Python form of the JSON columns the
`gmwm` command writes for the same data and options (docs/cli.md, "JSON"):

    import numpy as np, gmwm
    x = gmwm.simulate("WN(sigma2=1e-4)+RW(gamma2=1e-9)", 2**17, freq=100)
    w = gmwm.wv(x, freq=100)                       # w["levels"][j]["wv"], ["ci_low"], ...
    f = gmwm.fit(x, "WN+RW", freq=100)             # f["parameters"], f["gof"], ...
    s = gmwm.select(np.column_stack([x, x]), "AR1+WN+RW", freq=100)   # one entry per column
    a = gmwm.allan(x, freq=100, units="rad/s")     # a["allan"], a["noise_figures"] (N, K, B)
    g = gmwm.gap(np.column_stack([x]), freq=100, names=["gyro_x"], kalibr="imu.yaml")
                                                   # g["columns"][0]["headline"], ...
    n = gmwm.nav("select.json", ["truth", "wnrw", "imu.yaml*2"], outages=[(300, 360)])
                                                   # n["filters"][k]["verdict"], ["curves"] ...
    c = gmwm.gap_check(cases=3, n=2**14, families="STEP,DR")   # c["families"], c["confusion"]
    p = gmwm.plan(model="WN(sigma2=1e-8)+RW(gamma2=1e-14)", freq=100, unit="rad/s")
                                                   # p["columns"][0]["targets"][k]["seconds"]

`units` is the CLI's --units everywhere: one unit ("deg/s") or kind=unit pairs
("gyro=deg/s,accel=g", each column's kind from its name); a typo is refused. plan() takes the
CLI's --unit (one unit name, validated too).

Bad input raises gmwm.InputError (a ValueError) with the command's one-line message.
"""
from ._gmwm import DEFAULT_SEED, InputError, __version__, allan, fit, gap, gap_check, nav, plan, select, simulate, wv

__all__ = ["wv", "allan", "fit", "select", "gap", "gap_check", "nav", "plan", "simulate", "InputError", "DEFAULT_SEED", "__version__"]
