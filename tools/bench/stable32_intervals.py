#!/usr/bin/env python3
"""How far Stable32's printed confidence intervals can be reproduced (issue 48: "Greenhall
degrees of freedom and intervals equal Stable32's on PHASE.DAT to its printed digits").

    /usr/bin/python3 tools/bench/stable32_intervals.py build/gmwm SHARED_REFERENCE_STABILITY_DIR

For every octave row of Stable32 1.60's tables for PHASE.DAT below 100 degrees of freedom
(ADEV, OADEV, MDEV, TDEV, HDEV, OHDEV, TOTDEV; white FM, as Stable32 reads it everywhere
there), with gmwm's deviation (equal to Stable32's to 1e-12) and gmwm's Greenhall edf:

1. the bracket: the degrees of freedom nu for which the exact chi-square interval at
   Stable32's confidence (erf(1/sqrt 2) = 0.6827) rounds to BOTH printed ends. Where it is
   empty no edf at all reproduces the row with exact quantiles: the printed ends then carry
   an error of Stable32's quantile computation, whatever its edf;
2. the implied quantile probabilities: with gmwm's edf, the chi-square CDF at the quantiles
   the printed ends imply (exact: 0.841345 and 0.158655), and the spread the printing alone
   allows (half a unit of the last digit);
3. candidate quantile rules (exact; exact at 0.683 and 0.68; Wilson-Hilferty with the exact
   normal quantile, with Abramowitz and Stegun 26.2.23's, and with z(0.84), Stable32's rule
   beyond 100 edf), each scored by the ends it gives to half a printed unit.

Prints the rows and a summary; nothing is written.
"""
import json
import math
import os
import subprocess
import sys
import tempfile

from scipy.optimize import brentq
from scipy.special import erf
from scipy.stats import chi2, norm

KINDS = ["adev", "oadev", "mdev", "tdev", "hdev", "ohdev", "totdev"]
CONFIDENCE = erf(1 / math.sqrt(2))  # Stable32's "0.683" (docs/stability.md)
TAIL = (1 - CONFIDENCE) / 2
EXACT_DOF_LIMIT = 100  # beyond, Stable32's Wilson-Hilferty rule is reproduced (confidence.cc)


def half_unit(v):
    """Half a unit of the last digit of v printed as %.4e (Stable32's five digits)."""
    return 0.5 * 10 ** (int(f"{v:.4e}".split("e")[1]) - 4)


def stable32_rows(reference, kind):
    rows = []
    with open(os.path.join(reference, f"phase_dat_{kind}_octave.txt")) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            p = line.split()
            rows.append((int(p[0]), float(p[4]), float(p[6])))  # AF, min sigma, max sigma
    return rows


def gmwm_rows(gmwm, tmp, kind, factors):
    """gmwm's deviation and edf at the factors, white FM fixed (Stable32's noise there)."""
    out = os.path.join(tmp, "out.json")
    subprocess.run([gmwm, "stability", os.path.join(tmp, "phase.csv"), "--freq", "1", "--data", "phase", "--kind",
                    kind, "--taus", ",".join(map(str, factors)), "--noise-alpha", "0", "--json", out, "--quiet"],
                   check=True, stderr=subprocess.DEVNULL)
    with open(out) as f:
        d = json.load(f)["columns"][0]["deviations"][kind]
    return d["value"], d["edf"]


def wilson_hilferty(nu, z):
    a = 2 / (9 * nu)
    return nu * (1 - a + z * math.sqrt(a)) ** 3


def as_26_2_23(p):
    """Abramowitz and Stegun 26.2.23: the upper-tail normal quantile, |error| < 4.5e-4."""
    t = math.sqrt(-2 * math.log(p))
    return t - (2.515517 + 0.802853 * t + 0.010328 * t * t) / (1 + 1.432788 * t + 0.189269 * t * t + 0.001308 * t**3)


RULES = {
    "exact chi-square, 0.6827": lambda nu, p: chi2.ppf(p, nu),
    "exact chi-square, 0.683": lambda nu, p: chi2.ppf(0.5 + (p - 0.5) * 0.683 / CONFIDENCE, nu),
    "exact chi-square, 0.68": lambda nu, p: chi2.ppf(0.5 + (p - 0.5) * 0.68 / CONFIDENCE, nu),
    "Wilson-Hilferty, exact z": lambda nu, p: wilson_hilferty(nu, norm.ppf(p)),
    "Wilson-Hilferty, A&S 26.2.23 z": lambda nu, p: wilson_hilferty(nu, as_26_2_23(1 - p) if p > 0.5 else -as_26_2_23(p)),
    "Wilson-Hilferty, z(0.84)": lambda nu, p: wilson_hilferty(nu, norm.ppf(0.84) * (1 if p > 0.5 else -1)),
}


def dof_bracket(sigma, low, high):
    """The nu whose exact interval rounds to both printed ends: (from, to), empty if from > to."""
    def end(nu, p, target):
        return sigma * math.sqrt(nu / chi2.ppf(p, nu)) - target
    lo_a = brentq(end, 0.3, 1e6, args=(1 - TAIL, low - half_unit(low)))
    lo_b = brentq(end, 0.3, 1e6, args=(1 - TAIL, low + half_unit(low)))
    hi_a = brentq(end, 0.3, 1e6, args=(TAIL, high + half_unit(high)))
    hi_b = brentq(end, 0.3, 1e6, args=(TAIL, high - half_unit(high)))
    return max(lo_a, hi_a), min(lo_b, hi_b)


def main():
    gmwm, reference = sys.argv[1], sys.argv[2]
    with tempfile.TemporaryDirectory() as tmp:
        with open(os.path.join(reference, "PHASE.DAT")) as f:
            x = [line.strip() for line in f if line.strip() and not line.startswith("#")]
        with open(os.path.join(tmp, "phase.csv"), "w") as f:
            f.write("x\n" + "\n".join(x) + "\n")
        rows = []
        for kind in KINDS:
            ref = stable32_rows(reference, kind)
            value, edf = gmwm_rows(gmwm, tmp, kind, [r[0] for r in ref])
            rows += [(kind, m, edf[i], value[i], low, high) for i, (m, low, high) in enumerate(ref)
                     if edf[i] < EXACT_DOF_LIMIT]
    print("| kind | m | gmwm edf | nu reproducing both printed ends (exact quantiles) | "
          "P at the implied upper / lower quantile (exact 0.841345 / 0.158655) |")
    print("|---|---|---|---|---|")
    empty = outside = 0
    for kind, m, nu, sigma, low, high in rows:
        try:
            a, b = dof_bracket(sigma, low, high)
            bracket = "none" if a > b else f"{a:.3f} .. {b:.3f}"
            empty += a > b
            outside += a <= b and not a <= nu <= b
        except ValueError:
            bracket = "(no root)"
        p_up = chi2.cdf(nu * (sigma / low) ** 2, nu)
        p_lo = chi2.cdf(nu * (sigma / high) ** 2, nu)
        print(f"| {kind} | {m} | {nu:.3f} | {bracket} | {p_up:.5f} / {p_lo:.5f} |")
    print(f"\n{len(rows)} rows below {EXACT_DOF_LIMIT} edf: in {empty} no edf reproduces both ends with exact quantiles; "
          f"in {outside} one does but not gmwm's.\n")
    print("| quantile rule | ends to half a printed unit | largest miss (units) |")
    print("|---|---|---|")
    for name, q in RULES.items():
        hits = worst = 0
        for _, _, nu, sigma, low, high in rows:
            for ours, theirs in ((sigma * math.sqrt(nu / q(nu, 1 - TAIL)), low),
                                 (sigma * math.sqrt(nu / q(nu, TAIL)), high)):
                units = abs(ours - theirs) / (2 * half_unit(theirs))
                hits += units <= 0.5
                worst = max(worst, units)
        print(f"| {name} | {hits}/{2 * len(rows)} | {worst:.1f} |")


if __name__ == "__main__":
    main()
