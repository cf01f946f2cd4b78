#pragma once
// The HTML report's data of each study (html_report.h renders it), shared by the CLI and
// Python: one ReportColumn per analysed column with its WVs, fit or selection, Allan
// deviation and units, as the command draws it.

#include <optional>
#include <string>
#include <vector>

#include "gmwm/io/signal_reader.h"
#include "gmwm/pipeline/corrected_config.h"
#include "gmwm/pipeline/fit_study.h"
#include "gmwm/pipeline/gap_study.h"
#include "gmwm/pipeline/replicate_study.h"
#include "gmwm/pipeline/select_study.h"
#include "gmwm/pipeline/wv_study.h"
#include "gmwm/report/html_report.h"

namespace gmwm::report {

/// What reading said of the record, one sentence each: the samples missing (each scale from
/// the windows without one), where frequent gaps stop the long scales, increments and
/// decimation, and each column's held or interpolated samples. The report's header notes and
/// the web app's dataset facts.
std::vector<std::string> record_notes(const io::SignalSet& set);

/// The report's skeleton: one column per signal (name, n, rate, the file's unit), no results.
ReportData report_skeleton(const std::string& command, const io::SignalSet& set, const std::string& model_spec = {});

/// `units[k]` is column k's declared unit ("" when not declared: the file's own is kept);
/// `filter_rate` the Kalman table's rate in Hz.
ReportData wv_report_data(const io::SignalSet& set, const pipeline::WvStudy& study,
                          const std::vector<std::string>& units);
ReportData fit_report_data(const io::SignalSet& set, const pipeline::FitStudy& study, const std::string& model_spec,
                           const std::vector<std::string>& units, double filter_rate);
ReportData select_report_data(const io::SignalSet& set, const pipeline::SelectStudy& study,
                              const std::string& model_spec, const std::vector<std::string>& units, double filter_rate);
/// `baseline` is how the page names the baseline (the model, "fit SPEC" or the file).
ReportData gap_report_data(const io::SignalSet& set, const pipeline::GapStudy& study, const std::string& baseline,
                           const std::optional<pipeline::CorrectedConfig>& corrected);
/// One column per group (the primary recording's axis) with its replicates' WVs, the joint
/// fit, its test and bootstrap; `estimator` as replicate_estimator_text (study_text.h).
ReportData joint_fit_report_data(const io::SignalSet& set, const std::vector<pipeline::ReplicateGroup>& groups,
                                 const pipeline::JointFitStudy& study, const std::string& estimator);
/// As joint_fit_report_data with the recommended model's joint fit and the selection table.
ReportData joint_select_report_data(const io::SignalSet& set, const std::vector<pipeline::ReplicateGroup>& groups,
                                    const pipeline::JointSelectStudy& study, const std::string& estimator);

}  // namespace gmwm::report
