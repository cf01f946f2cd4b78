#include "gmwm/report/report_data.h"

namespace gmwm::report {
namespace {

// The WVs a fitted column draws: the one fitted first, the classical one beside a robust fit.
std::vector<WaveletVariance> drawn_wvs(const WaveletVariance& fitted, const std::optional<WaveletVariance>& classical) {
  return classical ? std::vector<WaveletVariance>{fitted, *classical} : std::vector<WaveletVariance>{fitted};
}

void set_unit(ReportColumn& column, const std::vector<std::string>& units, std::size_t k) {
  if (k < units.size() && !units[k].empty()) column.unit = units[k];
}

// What a fitted column (fit, select) draws beside its model: the WVs, the Allan deviation
// with its noise figures, the Kalman table's rate, the unit.
template <class ColumnStudy>
void fill_fitted(ReportColumn& column, const ColumnStudy& c, const std::vector<std::string>& units, std::size_t k,
                 double filter_rate) {
  column.wvs = drawn_wvs(c.wv, c.classical);
  column.allan = c.figures;
  column.filter_rate = filter_rate;
  set_unit(column, units, k);
}

// A group's joint analysis in its column: the replicates' WVs, the joint fit, the replicate
// block with the joint fit, test and bootstrap.
void fill_joint_column(ReportColumn& column, const pipeline::ReplicateGroup& group,
                       const std::vector<WaveletVariance>& wvs, const JointAnalysis& analysis,
                       const std::string& estimator) {
  column.wvs = wvs;
  column.fit = analysis.fit.joint;
  ReplicateReport r;
  r.sources = group.sources;
  for (std::size_t k = 0; k < group.series.size(); ++k) {
    r.n.push_back(static_cast<std::int64_t>(group.series[k].size()));
    r.missing.push_back(group.missing_samples(k));
  }
  r.estimator = estimator;
  r.joint = analysis.fit;
  r.test = analysis.test;
  r.bootstrap = analysis.bootstrap;
  column.replicates = std::move(r);
}

}  // namespace

std::vector<std::string> record_notes(const io::SignalSet& set) {
  std::vector<std::string> notes;
  for (const std::string& note : {io::gaps_summary(set), io::long_scales_note(set), io::conditioning_summary(set)})
    if (!note.empty()) notes.push_back(note);
  for (std::string& note : io::reading_notes(set)) notes.push_back(std::move(note));
  return notes;
}

ReportData report_skeleton(const std::string& command, const io::SignalSet& set, const std::string& model_spec) {
  ReportData r;
  r.command = command;
  r.input = set.path;
  r.model_spec = model_spec;
  for (const auto& s : set.signals) {
    ReportColumn c;
    c.name = s.name;
    c.n = static_cast<std::int64_t>(s.values.size());
    c.freq = set.freq;
    c.freq_known = set.freq_known;
    c.unit = s.unit;
    r.columns.push_back(std::move(c));
  }
  r.notes = record_notes(set);
  return r;
}

ReportData wv_report_data(const io::SignalSet& set, const pipeline::WvStudy& study,
                          const std::vector<std::string>& units) {
  ReportData rep = report_skeleton("wv", set);
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    const pipeline::WvColumnStudy& c = study.columns[k];
    rep.columns[k].wvs =
        c.robust ? std::vector<WaveletVariance>{c.robust->classical, c.wv} : std::vector<WaveletVariance>{c.wv};
    rep.columns[k].allan = c.allan;
    set_unit(rep.columns[k], units, k);
  }
  return rep;
}

ReportData fit_report_data(const io::SignalSet& set, const pipeline::FitStudy& study, const std::string& model_spec,
                           const std::vector<std::string>& units, double filter_rate) {
  ReportData rep = report_skeleton("fit", set, model_spec);
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    fill_fitted(rep.columns[k], study.columns[k], units, k, filter_rate);
    rep.columns[k].fit = study.columns[k].fit;
  }
  return rep;
}

ReportData select_report_data(const io::SignalSet& set, const pipeline::SelectStudy& study,
                              const std::string& model_spec, const std::vector<std::string>& units,
                              double filter_rate) {
  ReportData rep = report_skeleton("select", set, model_spec);
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    fill_fitted(rep.columns[k], study.columns[k], units, k, filter_rate);
    rep.columns[k].selection = study.columns[k].selection;
  }
  return rep;
}

ReportData gap_report_data(const io::SignalSet& set, const pipeline::GapStudy& study, const std::string& baseline,
                           const std::optional<pipeline::CorrectedConfig>& corrected) {
  ReportData rep = report_skeleton("gap", set, baseline);
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    const pipeline::GapColumnStudy& c = study.columns[k];
    rep.columns[k].wvs = {c.wv, c.robust_wv};
    rep.columns[k].gap = c.result;
    rep.columns[k].conversions = c.conversions;
    if (!c.unit.empty()) rep.columns[k].unit = c.unit;
  }
  rep.corrected = corrected;
  return rep;
}

ReportData joint_fit_report_data(const io::SignalSet& set, const std::vector<pipeline::ReplicateGroup>& groups,
                                 const pipeline::JointFitStudy& study, const std::string& estimator) {
  ReportData rep = report_skeleton("fit", set, study.model_spec);
  for (std::size_t i = 0; i < groups.size(); ++i)
    fill_joint_column(rep.columns[i], groups[i], study.groups[i].wvs, study.groups[i].analysis, estimator);
  return rep;
}

ReportData joint_select_report_data(const io::SignalSet& set, const std::vector<pipeline::ReplicateGroup>& groups,
                                    const pipeline::JointSelectStudy& study, const std::string& estimator) {
  ReportData rep = report_skeleton("select", set, study.model_spec);
  for (std::size_t i = 0; i < groups.size(); ++i) {
    fill_joint_column(rep.columns[i], groups[i], study.wvs[i], study.recommended[i], estimator);
    rep.columns[i].replicates->selection = study.results[i];
  }
  return rep;
}

}  // namespace gmwm::report
