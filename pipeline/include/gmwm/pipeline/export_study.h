#pragma once
// The export study (what `gmwm export` runs): the fitted noise parameters of every column
// in the exact form a consumer reads (io/export.h), from a fit/select result's columns or
// from a data set fitted first, with the inflation given or derived so that a WN + RW
// filter is not optimistic (--consistent-for, consistent_inflation in nav_study.h).
// report::export_document and report::export_text render it.

#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/wavelet_variance.h"
#include "gmwm/io/export.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/io/units.h"
#include "gmwm/pipeline/nav_study.h"

namespace gmwm::pipeline {

/// A data set whose fit failed on a column: nothing usable to export (the CLI's exit 1).
class UnusableFit : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// How a data set is fitted before its export: as `gmwm fit` weighs by default (classical
/// WV, Omega from the model), estimates only (no inference).
struct ExportFitOptions {
  ModelSpec model;  ///< e.g. "WN+RW" (checked when assigned)
  WvOptions wv;
  /// max_evaluations, alpha and seed are used; omega and inference are the study's.
  FitOptions fit;
  /// Declared units per sensor kind; a column's unit is else its file's own (EuRoC header),
  /// never assumed.
  std::map<io::SensorKind, io::Unit> units;
  /// Every column is this sensor (else each column's name tells it).
  std::optional<io::SensorKind> sensor;

  std::string Validate() const;
};

/// Every column of `set` fitted with options.model, as the exporter takes it, with N, K, B
/// read against the data's own Allan deviation. `warnings` gets a line per column whose fit
/// did not converge. Throws InputError for a bad model or a column without a known unit,
/// UnusableFit (naming the column) when a fit fails.
std::vector<io::ExportColumn> fitted_export_columns(const io::SignalSet& set, const ExportFitOptions& options,
                                                    std::vector<std::string>& warnings);

struct ExportStudyOptions {
  /// Format, aggregation, inflation, rate, rostopic.
  io::ExportOptions format;
  /// Derive the inflation (N and K factors) that keeps a WN + RW filter updated at
  /// update_rate Hz from being optimistic over `horizon` s against the full fitted model;
  /// only for the WN + RW formats, and then format.inflate must be left at 1.
  std::optional<ConsistencyOptions> consistent_for;

  std::string Validate() const;
};

struct ExportStudy {
  /// The settings as applied (with consistent_for: its inflation and reason).
  io::ExportOptions options;
  /// The file's text, its sidecar, the per-column and written figures, warnings.
  io::ExportResult result;
  /// Where the columns came from, one line (the file's header says it too).
  std::string source;
  std::optional<ConsistencyOptions> consistency;
  std::optional<ConsistentInflation> consistent;
};

/// Renders `columns` (from io::read_result_columns or fitted_export_columns) in the format.
/// Throws InputError for invalid options, and with consistent_for when a sensor's model is
/// missing on an axis (naming `who`, the input).
ExportStudy study_export(const std::vector<io::ExportColumn>& columns, const std::string& source,
                         const std::string& who, const ExportStudyOptions& options);

}  // namespace gmwm::pipeline
