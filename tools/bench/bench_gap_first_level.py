"""The gap diagnosis of held and interpolated records (issue 47): RealSense-like records (an
accelerometer's WN + RW measured at 200 Hz, put on 400 Hz stamps by copying or by linear
interpolation at a random phase) diagnosed against their own true model, every level
compared (first_level=1) and from the auto first level (gmwm gap's default). The truth is
the baseline, so every detection is a false alarm (nominal rate: the 5% level) and every
effect named is invented. Counts the detections, the records where an effect was named and
the effects named.

    PYTHONPATH=build/python python3 tools/bench/bench_gap_first_level.py [records] [log2 length]
"""
import collections
import sys
import warnings

import gmwm
from bench_first_level import GAMMA2, SIGMA2, record


def main():
    records = int(sys.argv[1]) if len(sys.argv) > 1 else 50
    n = 1 << (int(sys.argv[2]) if len(sys.argv) > 2 else 16)
    # The true model on the 400 Hz stamps: the white noise's density kept (sigma2 x 2), the
    # walk's increments spread over two samples (gamma2 / 2).
    truth = f"WN(sigma2={2 * SIGMA2})+RW(gamma2={GAMMA2 / 2})"
    print(f"{records} records of {n} samples at 400 Hz against their true model {truth}; 60 replicates each")
    print("| fill | levels compared | gap detected (false alarm) | an effect named | effects named | first level |")
    print("|---|---|---|---|---|---|")
    for fill in ("copy", "linear"):
        for first in (1, "auto"):
            detected = named = 0
            effects: collections.Counter[str] = collections.Counter()
            levels = []
            for i in range(records):
                x = record(1000 + i, n, fill)
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", gmwm.RepeatedSamplesWarning)
                    (c,) = gmwm.gap(x, freq=400, model=truth, replicates=60, seed=i, first_level=first).columns
                detected += c.gap.detected
                steps = [s.effect for s in c.attribution.steps if s.effect != "REPARAMETERISE"]
                named += bool(steps)
                effects.update(steps)
                levels.append(c.gap.first_level)
            said = ", ".join(f"{e} {k}" for e, k in effects.most_common()) or "none"
            print(f"| {fill} | {'every' if first == 1 else 'auto'} | {detected}/{records} | {named}/{records} | "
                  f"{said} | {min(levels)}-{max(levels)} |")


if __name__ == "__main__":
    main()
