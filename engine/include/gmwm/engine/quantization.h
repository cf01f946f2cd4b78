#pragma once
// The rounding step of a series: sensors output x_t = q round(y_t / q) for a quantum q (the
// LSB), and a CSV printed with a fixed number of decimals does the same. The robust WV's
// contamination check (robust/contamination.h) and the detection of repeated samples
// (repeated_samples.h) both read the data against this lattice.

#include <cstdint>

namespace gmwm {

struct Quantization {
  bool detected = false;
  double quantum = 0.0;           ///< the rounding step q (LSB), 0 when not detected
  double on_lattice_share = 0.0;  ///< share of the differences that are multiples of q
};

/// The rounding step: the smallest non-zero |x_t - x_{t-1}|, accepted when at least
/// kLatticeShare (0.99) of all differences are integer multiples of it (to a relative
/// kLatticeTolerance, 1e-6).
Quantization detect_quantization(const double* x, std::int64_t n);

}  // namespace gmwm
