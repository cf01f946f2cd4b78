#pragma once
// Replicates on the command line (`--joint FILE[:COLUMN] ...`): further recordings of the
// sensor whose INPUT columns are being fitted. FILE alone adds that file's columns of the
// same names (axis-wise replicates: one joint model per axis); FILE:COLUMN adds one
// column as a replicate of INPUT's single selected column.

#include <optional>
#include <string>
#include <vector>

#include "common.h"
#include "units_tables.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/model.h"
#include "gmwm/report/html_report.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/pipeline/replicate_study.h"
#include "gmwm/robust/robust_wv.h"

namespace gmwm::cli {

/// One axis and its replicates, INPUT's column first.
using ReplicateGroup = pipeline::ReplicateGroup;

/// The groups for INPUT's selected columns and the --joint entries (read here, at INPUT's
/// rate). Throws InputError (one line naming the entry) when an entry names a column and
/// INPUT has several selected, a file lacks one of INPUT's columns, a rate differs from
/// INPUT's, or a recording is given twice.
std::vector<ReplicateGroup> read_replicates(const io::SignalSet& input, const std::vector<std::string>& entries,
                                            const InputOptions& options);

/// The file of a --joint entry (FILE[:COLUMN]), for the output safety checks.
std::string replicate_path(const std::string& entry);

/// "classical WV" or "robust WV (Gaussian efficiency E)".
std::string replicate_estimator_text(const robust::RobustWvOptions* robust);

/// The report's replicate block of a group (sources, lengths, estimator); the caller adds
/// the joint fit, test and selection.
report::ReplicateReport replicate_report(const ReplicateGroup& group, const std::string& estimator);

/// The joint model's tables in the data's units, as a single fit shows them: continuous
/// parameters, noise figures (when given) and the Kalman terms at `filter_rate` Hz.
std::string joint_physical_tables(const ReplicateGroup& group, const io::SignalSet& set, const FitResult& joint,
                                  const std::optional<ChosenFigures>& figures, const UnitsOptions& units,
                                  double filter_rate);

/// A report column of a group's joint analysis: its replicates' WVs, the joint fit, the
/// replicate block with the joint fit, test and bootstrap.
void fill_joint_report_column(report::ReportColumn& column, const ReplicateGroup& group,
                              const std::vector<WaveletVariance>& wvs, const JointAnalysis& analysis,
                              const std::string& estimator);

}  // namespace gmwm::cli
