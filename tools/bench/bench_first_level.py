"""Fitting above the smoothed scales (issue 47, item 2), a coverage study: RealSense-like
records (an accelerometer's WN + RW measured at 200 Hz, put on 400 Hz stamps by copying or
by linear interpolation at a random phase), WN+RW fitted on every level and from the auto
first level. Counts the goodness-of-fit rejections at 5% and how often the white noise's
95% interval covers the measured noise's sigma2 (2 x the 200 Hz value at 400 Hz), with
the median N ratio.

    PYTHONPATH=build/python python3 tools/bench/bench_first_level.py [records] [log2 length]
"""
import sys
import warnings

import numpy as np

import gmwm

SIGMA2, GAMMA2 = 4e-4, 1e-10  # the 200 Hz measurement's white noise and random walk


def record(seed, n, fill):
    a = gmwm.simulate(f"WN(sigma2={SIGMA2})+RW(gamma2={GAMMA2})", n // 2 + 2, freq=200, seed=seed)
    rng = np.random.default_rng(seed)
    u = np.arange(n) / 2 + rng.uniform(0, 1)
    k = np.floor(u).astype(int)
    return a[k] if fill == "copy" else a[k] + (u - k) * (a[k + 1] - a[k])


def main():
    records = int(sys.argv[1]) if len(sys.argv) > 1 else 200
    n = 1 << (int(sys.argv[2]) if len(sys.argv) > 2 else 16)
    truth = 2 * SIGMA2  # the white noise's sigma2 on the 400 Hz stamps
    print(f"{records} records of {n} samples at 400 Hz; WN+RW; truth sigma2 = {truth:g}")
    print("| fill | levels fitted | GoF rejected at 5% | 95% interval covers sigma2 | median N / truth | first level |")
    print("|---|---|---|---|---|---|")
    for fill in ("copy", "linear"):
        for first in (1, "auto"):
            rejected = covered = 0
            ratios, levels = [], []
            for i in range(records):
                x = record(1000 + i, n, fill)
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", gmwm.RepeatedSamplesWarning)
                    f = gmwm.fit(x, "WN+RW", freq=400, first_level=first, seed=i)
                p = f.parameter("sigma2")
                rejected += f.gof.p_value < 0.05
                covered += p.ci_low <= truth <= p.ci_high
                ratios.append(np.sqrt(p.value / truth))
                levels.append(f.first_level)
            print(f"| {fill} | {'every' if first == 1 else 'auto'} | {rejected}/{records} | {covered}/{records} | "
                  f"{np.median(ratios):.4f} | {min(levels)}-{max(levels)} |")


if __name__ == "__main__":
    main()
