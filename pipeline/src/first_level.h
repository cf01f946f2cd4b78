#pragma once
// The studies' first fitted level per column (fit, select): internal to the pipeline.

#include <string>
#include <vector>

#include "gmwm/engine/fit.h"
#include "gmwm/engine/wavelet_variance.h"
#include "gmwm/io/signal_reader.h"

namespace gmwm::pipeline::detail {

/// A column's first fitted level and why (an empty reason at level 1).
struct FittedLevels {
  int first = 1;
  std::string reason;
};

/// What a study does from its first level on: fit (fit, select) or compare (gap).
enum class LevelUse { kFitted, kCompared };

/// Column k's first level (`option`, or with kAutoFirstLevel its first_fit_level) and why,
/// the reason saying the finer levels were not `use`d. Throws InputError naming the column
/// when the levels left cannot hold `model`.
FittedLevels fitted_level(const io::SignalSet& set, std::size_t k, const WaveletVariance& wv, const Model& model,
                          int option, LevelUse use);

/// Each column's first fitted level: `option` (a level, or kAutoFirstLevel: the first level
/// its held or interpolated samples leave all but unbiased, first_fit_level). Throws
/// InputError naming the column when the levels left cannot hold `model`.
std::vector<FittedLevels> fitted_levels(const io::SignalSet& set, const std::vector<WaveletVariance>& wvs,
                                        const Model& model, int option);

/// The WVs a fit takes: each from its first fitted level on.
std::vector<WaveletVariance> fitted_wvs(const std::vector<WaveletVariance>& wvs,
                                        const std::vector<FittedLevels>& levels);

/// After a fit on fitted_wvs: the model's WV at every level of `wv` (the finer ones too, to
/// read the smoothing off) and the reason as the fit's first note.
void restore_levels(FitResult& fit, const WaveletVariance& wv, const FittedLevels& levels);

}  // namespace gmwm::pipeline::detail
