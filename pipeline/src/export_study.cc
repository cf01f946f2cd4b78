// The export study: the columns (read from a result or fitted here), the inflation given or
// derived for a consistent WN + RW filter, the file rendered (io/export.h).
#include "gmwm/pipeline/export_study.h"

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/noise_figures.h"
#include "gmwm/engine/parallel.h"
#include "column_wvs.h"
#include "usable_wv.h"

namespace gmwm::pipeline {
namespace {

// A column's unit: declared, else the file's own (EuRoC's header units); never assumed.
io::Unit column_unit(const io::SignalSet& set, const io::Signal& s, io::SensorKind kind,
                     const std::map<io::SensorKind, io::Unit>& units) {
  if (const auto given = units.find(kind); given != units.end()) return given->second;
  if (!s.unit.empty()) {
    try {
      return io::parse_unit(s.unit, kind);
    } catch (const InputError& e) {
      throw InputError(set.path + ": column '" + s.name + "': its header gives the unit '" + s.unit +
                       "', which is not a " + io::to_string(kind) + " unit (" + e.what() + "); give --units");
    }
  }
  throw InputError(set.path + ": column '" + s.name + "': the file does not say its unit; give --units " +
                   io::to_string(kind) + "=UNIT (" +
                   (kind == io::SensorKind::kGyro ? "rad/s, deg/s or deg/h" : "m/s^2, g or mg") + ")");
}

// The WN + RW figures a file would hold (SI), as the filter model they make, on the axes
// the truth has: per axis for a per-axis export, else the kind's combined figures.
nav::ImuModel written_model(const io::ExportResult& r, const nav::ImuModel& truth) {
  nav::ImuModel m;
  m.label = "the exported WN + RW figures";
  for (const io::KindExport& k : r.kinds) {
    const bool gyro = k.kind == io::SensorKind::kGyro;
    const auto& axes = gyro ? truth.gyro : truth.accel;
    for (std::size_t a = 0; a < 3; ++a) {
      const io::WrittenNoise& w = k.per_axis ? k.axes[a] : k.combined;
      const double f = axes[a].freq;
      const Model model = parse_model(w.random_walk > 0.0 ? "WN+RW" : "WN", ProcessContext{f, true});
      Eigen::VectorXd theta(model.num_parameters());
      theta(0) = w.noise_density * w.noise_density * f;                       // sigma2 = N^2 f
      if (w.random_walk > 0.0) theta(1) = w.random_walk * w.random_walk / f;  // gamma2 = K^2 / f
      (gyro ? m.gyro : m.accel)[a] = nav::SensorModel{model, theta, f, 1.0};
    }
  }
  return m;
}

}  // namespace

std::string ExportFitOptions::Validate() const {
  if (model.empty()) return "the model is empty";
  if (std::string why = wv.Validate(); !why.empty()) return why;
  return fit.Validate();
}

std::vector<io::ExportColumn> fitted_export_columns(const io::SignalSet& set, const ExportFitOptions& options,
                                                    std::vector<std::string>& warnings) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError(why);
  const Model model = options.model.bind(ProcessContext{set.freq, set.freq_known});
  std::vector<io::ExportColumn> columns(set.signals.size());
  for (std::size_t k = 0; k < set.signals.size(); ++k) {
    const io::Signal& s = set.signals[k];
    io::ExportColumn& c = columns[k];
    c.name = s.name;
    c.kind = options.sensor ? *options.sensor : io::sensor_kind_of_column(s.name);
    c.freq = set.freq;
    c.n = static_cast<std::int64_t>(s.values.size());
    c.unit = column_unit(set, s, c.kind, options.units);
  }
  std::vector<std::span<const double>> series;
  for (const auto& s : set.signals) series.emplace_back(s.values);
  // A record with gaps: the complete windows' WV and Allan deviation (gappy_column_wvs).
  detail::ColumnWvs curves;
  if (set.missing.empty())
    curves.wvs = classical_wv(series, options.wv);
  else
    curves = detail::gappy_column_wvs(set, options.wv, AllanOptions{});
  const std::vector<WaveletVariance>& wvs = curves.wvs;
  detail::check_usable_wvs(set, wvs, true);
  for (const auto& w : wvs) check_model_fits_levels(model, w.levels());
  FitOptions fo = options.fit;
  fo.inference = false;          // the export needs the estimates only
  fo.omega = OmegaKind::kModel;  // as `gmwm fit` weighs by default
  std::vector<FitResult> fits(wvs.size());
  parallel_for(std::size_t{0}, wvs.size(), [&](std::size_t k) { fits[k] = fit_gmwm(wvs[k], model, fo); });
  for (std::size_t k = 0; k < fits.size(); ++k) {
    const FitResult& r = fits[k];
    if (r.status == FitStatus::kFailed || r.theta.size() != r.model.num_parameters() || !r.theta.allFinite())
      throw UnusableFit("column '" + set.signals[k].name + "': the fit of " + options.model.text() + " failed" +
                        (r.message.empty() ? "" : ": " + r.message) + "; nothing written");
    if (r.status == FitStatus::kNotConverged)
      warnings.push_back("column '" + set.signals[k].name + "': the fit did not converge" +
                         (r.message.empty() ? "" : ": " + r.message));
    columns[k].model = r.model;
    columns[k].theta = r.theta;
    // N, K, B against the data's own Allan deviation (noise_figures.h).
    const FigureReport figures = curves.allan.empty()
                                     ? noise_figure_report(set.signals[k].values, set.freq, r.model, r.theta, nullptr)
                                     : noise_figure_report(curves.allan[k], r.model, r.theta, nullptr);
    columns[k].figures = io::export_figures(figures.chosen);
  }
  return columns;
}

std::string ExportStudyOptions::Validate() const {
  if (std::string why = format.Validate(); !why.empty()) return why;
  if (!consistent_for) return {};
  if (format.format == io::ExportFormat::kGzSdf || format.format == io::ExportFormat::kRotors)
    return "--consistent-for: for the WN + RW formats (kalibr, openvins, vins, orbslam3, basalt); " +
           std::string(io::to_string(format.format)) + " writes the Gauss-Markov bias itself";
  if (format.inflate != 1.0 || format.inflate_walk)
    return "--consistent-for derives the inflation; leave out --inflate";
  if (std::string why = consistent_for->Validate(); !why.empty()) return "--consistent-for: " + why;
  return {};
}

ExportStudy study_export(const std::vector<io::ExportColumn>& columns, const std::string& source,
                         const std::string& who, const ExportStudyOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError(why);
  ExportStudy study;
  study.options = options.format;
  study.source = source;
  study.consistency = options.consistent_for;
  if (options.consistent_for) {
    NavModelInfo truth;
    try {
      truth = imu_model_of(columns, who);
    } catch (const InputError& e) {
      throw InputError(std::string("--consistent-for needs the models of both sensors on every axis (gyroscope and "
                                   "accelerometer columns): ") +
                       e.what());
    }
    const io::ExportResult plain = io::render_export(columns, study.options, source);
    study.consistent = consistent_inflation(truth.model, written_model(plain, truth.model), *options.consistent_for);
    study.options.inflate = study.consistent->white;
    study.options.inflate_walk = study.consistent->factor;
    study.options.inflation_reason = study.consistent->reason;
  }
  study.result = io::render_export(columns, study.options, source);
  return study;
}

}  // namespace gmwm::pipeline
