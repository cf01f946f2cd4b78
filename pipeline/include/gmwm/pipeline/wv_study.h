#pragma once
// The wavelet-variance study of a signal set: each column's classical WV, or its robust WV
// with the classical one beside it, the rounding (quantization) check and the per-level
// contamination diagnostic; optionally the overlapping Allan deviation and the noise
// figures read off it. What `gmwm wv` runs; report::wv_document writes it.

#include <optional>
#include <string>
#include <vector>

#include "gmwm/engine/allan.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/noise_figures.h"
#include "gmwm/engine/wavelet_variance.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/robust/contamination.h"
#include "gmwm/robust/robust_wv.h"

namespace gmwm::pipeline {

struct WvStudyOptions {
  /// Levels and alpha of the classical WV.
  WvOptions wv;
  /// The robust WV (reported), the classical one beside it.
  std::optional<robust::RobustWvOptions> robust;
  /// The Allan deviation and its noise figures (needs a known rate).
  std::optional<AllanOptions> allan;

  /// Empty when valid, else what is wrong.
  std::string Validate() const;
};

/// The robust side of a column: the classical WV, the rounding check, the per-level diagnostic.
struct RobustWvView {
  WaveletVariance classical;
  robust::Quantization quantization;
  std::vector<robust::LevelDiagnostic> diagnostic;
};

struct WvColumnStudy {
  std::string name;
  /// The WV reported: the robust one when asked, else the classical one.
  WaveletVariance wv;
  std::optional<RobustWvView> robust;
  /// The data's Allan deviation and noise figures (WvStudyOptions::allan).
  std::optional<FigureReport> allan;
};

struct WvStudy {
  std::vector<WvColumnStudy> columns;
  /// Stage times: the WVs, the Allan deviations from the same transforms (0 without one).
  double wv_seconds = 0.0, allan_seconds = 0.0;
  /// The levels asked (WvStudyOptions::wv.levels; 0: every level the record holds), so a
  /// level the gaps leave without a window is told from one not asked.
  int levels_asked = 0;
};

/// Runs the study on every column of `set` (the Allan deviations in parallel). Throws
/// InputError for invalid options, or an Allan deviation asked of data without a known rate.
WvStudy study_wv(const io::SignalSet& set, const WvStudyOptions& options);

}  // namespace gmwm::pipeline
