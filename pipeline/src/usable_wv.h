#pragma once
// The studies' check that every column's wavelet variance can be used (engine's
// wv_range_problem), as an InputError naming the file and the column: a constant column
// given as an array (Python), values whose squares underflow or overflow a double, or a WV
// outside the range a fit can take.
#include <span>
#include <string>
#include <vector>

#include "gmwm/engine/error.h"
#include "gmwm/engine/wavelet_variance.h"
#include "gmwm/io/signal_reader.h"

namespace gmwm::pipeline::detail {

/// "FILE: column 'NAME': " ("column 'NAME': " without a file, as for arrays).
inline std::string column_place(const std::string& path, const std::string& name) {
  return (path.empty() ? std::string() : path + ": ") + "column '" + name + "': ";
}

/// Throws InputError(place + why) when wv (of x) is unusable.
inline void check_usable_wv(const std::string& place, const WaveletVariance& wv, std::span<const double> x,
                            bool for_fit) {
  if (const std::string why = wv_range_problem(wv, x, for_fit); !why.empty()) throw InputError(place + why);
}

/// The same for every column of `set` (wvs[k] of column k).
inline void check_usable_wvs(const io::SignalSet& set, const std::vector<WaveletVariance>& wvs, bool for_fit) {
  for (std::size_t k = 0; k < wvs.size() && k < set.signals.size(); ++k)
    check_usable_wv(column_place(set.path, set.signals[k].name), wvs[k], set.signals[k].values, for_fit);
}

}  // namespace gmwm::pipeline::detail
