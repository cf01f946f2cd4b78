// The gap study as a pipeline of named stages (docs/gap.md):
//   take_temperature -> resolve_baselines -> wavelet_variances -> baseline_values
//   (simulator biases as RW, unit check, or the fit) -> diagnose_columns -> cross-axis.
#include "gmwm/pipeline/gap_study.h"
#include "column_wvs.h"
#include "first_level.h"
#include "usable_wv.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <span>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/robust/robust_wv.h"
#include "gmwm/engine/number_text.h"

namespace gmwm::pipeline {
namespace {

// A simulator's Gauss-Markov bias whose correlation time is at least this many records
// long is a random walk over the record: its WV differs from RW(gamma2 = its innovation
// variance)'s by about tau / (2 T) relative, at most 5% at the coarsest scale.
constexpr double kRandomWalkLikeRecords = 10.0;

// The finest levels compared for a unit mix-up (white noise dominates there on an IMU).
constexpr int kUnitCheckLevels = 3;

std::string num(double x, int digits) { return significant(x, digits); }

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Stage 1: the temperature column out of the set.
std::vector<double> take_temperature(io::SignalSet& set, const std::string& column) {
  if (column.empty()) return {};
  std::string names;
  for (auto it = set.signals.begin(); it != set.signals.end(); ++it) {
    if (it->name == column) {
      std::vector<double> t = it->values.to_vector();
      set.signals.erase(it);
      if (set.signals.empty()) throw InputError("--temperature '" + column + "': no other column is left to diagnose");
      return t;
    }
    names += (names.empty() ? "" : ", ") + it->name;
  }
  throw InputError("--temperature '" + column + "': no such column among those read (" + names +
                   "); include it in --columns");
}

// Stage 2: each column's baseline model (values still to be set) and its conversions.
struct Baselines {
  std::vector<Model> models;
  std::vector<std::vector<std::string>> conversions;
  std::string source;
};

Baselines resolve_baselines(const io::SignalSet& set, const GapStudyOptions& o, const ProcessContext& ctx) {
  const std::size_t K = set.signals.size();
  Baselines b{std::vector<Model>(K), std::vector<std::vector<std::string>>(K), {}};
  if (const auto* c = std::get_if<ConfigBaseline>(&o.baseline)) {
    b.source = c->config.source;
    for (std::size_t k = 0; k < K; ++k) {
      const io::SensorKind kind = o.sensor ? *o.sensor : io::sensor_kind_of_column(set.signals[k].name);
      // The kind's model, or the column's axis's when the simulator's axes differ.
      auto sb = io::baseline_for_column(c->config, kind, set.signals[k].name);
      if (!sb)
        throw InputError(c->path + ": every " + std::string(io::to_string(kind)) +
                         " figure is zero or absent, nothing to compare column '" + set.signals[k].name + "' with");
      b.models[k] = std::move(sb->model);
      b.conversions[k] = std::move(sb->conversions);
    }
    return b;
  }
  const bool fit = std::holds_alternative<FitBaseline>(o.baseline);
  const ModelSpec& given = fit ? std::get<FitBaseline>(o.baseline).spec : std::get<ModelBaseline>(o.baseline).spec;
  const std::string& spec = given.text();
  const Model m = given.bind(ctx);
  if (!fit) {
    const Eigen::VectorXd v = m.given_values();
    if (const std::string why = m.validate(v); !why.empty() || !v.allFinite())
      throw InputError("--model '" + spec +
                       "': give every parameter's value (SPEC_WITH_VALUES), e.g. "
                       "WN(sigma2=2.5e-5)+RW(gamma2=1e-12)");
  }
  b.source = fit ? "fit " + spec : "model";
  std::fill(b.models.begin(), b.models.end(), m);
  return b;
}

// Stage 3: classical and robust WVs of every column (on a record with gaps, from the
// windows without one).
void wavelet_variances(const io::SignalSet& set, const WvOptions& o, std::vector<WaveletVariance>& wvs,
                       std::vector<WaveletVariance>& robust_wvs) {
  std::vector<std::span<const double>> series;
  for (const auto& s : set.signals) series.emplace_back(s.values);
  wvs = set.missing.empty() ? classical_wv(series, o) : detail::gappy_column_wvs(set, o, std::nullopt).wvs;
  detail::check_usable_wvs(set, wvs, true);
  robust::RobustWvOptions r;
  r.levels = o.levels;
  r.alpha = o.alpha;
  robust_wvs = detail::robust_column_wvs(set, r);
}

// A simulator's bias with a correlation time of many records replaced by the random walk
// it is over the record, said in the conversions: a Kalibr yaml and an SDF or RotorS file
// carrying the same densities then give the same baseline (and the same diagnosis).
// Nothing else is simplified: a term too small to show in one record's WV still belongs
// to the simulator's noise.
void random_walk_like(Model& base, Eigen::VectorXd& theta, std::int64_t n, std::vector<std::string>& conversions) {
  std::vector<Component> comps;
  std::vector<double> values;
  bool changed = false;
  for (int c = 0; c < base.num_components(); ++c) {
    const Component& comp = base.components()[static_cast<std::size_t>(c)];
    const Process& p = *comp.process;
    const double* th = theta.data() + base.offset(c);
    const std::span<const double> values_c(th, static_cast<std::size_t>(p.size()));
    const double T = p.role() == ProcessRole::kBias ? p.correlation_samples(values_c).value_or(0.0) : 0.0;
    const std::vector<SimplerForm> forms = p.simpler_forms(values_c);
    const auto walk = std::find_if(forms.begin(), forms.end(),
                                   [](const SimplerForm& f) { return f.process->role() == ProcessRole::kWalk; });
    if (T >= kRandomWalkLikeRecords * static_cast<double>(n) && walk != forms.end()) {
      comps.push_back(Component{walk->process, walk->theta});
      values.insert(values.end(), walk->theta.begin(), walk->theta.end());
      conversions.push_back("over this record (" + std::to_string(n) + " samples) the Gauss-Markov bias " + p.name() +
                            " (correlation time " + num(T, 3) + " samples, " + num(T / static_cast<double>(n), 3) +
                            " records) is RW-like: RW(gamma2 = its innovation variance " + num(walk->theta[0], 6) +
                            "), as a random-walk density gives");
      changed = true;
      continue;
    }
    comps.push_back(comp);
    values.insert(values.end(), th, th + p.size());
  }
  if (!changed) return;
  Eigen::VectorXd t = Eigen::Map<Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
  base = Model(std::move(comps)).canonical(&t);
  theta = t;
}

}  // namespace

// A data / baseline ratio at the finest levels near a unit factor ((180/pi)^2 for deg/s
// read as rad/s, 9.80665^2 for m/s^2 read as g, ...) is a unit mix-up, not a gap: stop
// with one line naming the --units that fits.
void check_baseline_units(const std::string& path, const std::string& column, const WaveletVariance& wv,
                          const Model& base, const Eigen::VectorXd& theta, std::optional<io::SensorKind> sensor,
                          const std::map<io::SensorKind, io::Unit>& units) {
  io::SensorKind kind;
  try {
    kind = sensor ? *sensor : io::sensor_kind_of_column(column);
  } catch (const InputError&) {
    return;  // neither a gyro nor an accelerometer: no unit to suggest
  }
  const Eigen::VectorXd nu = base.wv(theta, wv.tau);
  std::vector<double> r;
  for (int j = 0; j < std::min(kUnitCheckLevels, wv.levels()); ++j)
    r.push_back(wv.wv[static_cast<std::size_t>(j)] / nu(j));
  if (r.empty()) return;
  std::sort(r.begin(), r.end());
  const double ratio = r[r.size() / 2];
  const io::Unit declared = units.count(kind) ? units.at(kind) : io::si_unit(kind);
  const auto s = io::suggest_unit(ratio, kind, declared);
  if (!s) return;
  throw InputError(path + ": column '" + column + "': its WV at the finest scales is " + num(ratio, 3) +
                   " x the baseline's, near (" + s->unit.name + " per " + declared.name + ")^2 = " + num(s->factor, 4) +
                   ": the data look like " + s->unit.name + ", not " + declared.name + "; give --units " +
                   io::to_string(kind) + "=" + s->unit.name +
                   " (or --no-unit-check if the sensor really is that far "
                   "from the baseline)");
}

namespace {

// A column's WV from its first compared level on (all of it at level 1).
WaveletVariance compared(const WaveletVariance& wv, const detail::FittedLevels& levels) {
  return levels.first == 1 ? wv : drop_fine_levels(wv, levels.first);
}

// Stage 4: the baseline's values on each column: as given (a simulator's long biases as
// RW, then the unit check), or fitted; both on the levels compared.
void baseline_values(const io::SignalSet& set, const GapStudyOptions& o,
                     const std::vector<detail::FittedLevels>& levels, GapStudy& study) {
  const bool config = std::holds_alternative<ConfigBaseline>(o.baseline);
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    GapColumnStudy& c = study.columns[k];
    const WaveletVariance wv = compared(c.wv, levels[k]);
    check_model_fits_levels(c.baseline, wv.levels());
    if (const auto* f = std::get_if<FitBaseline>(&o.baseline)) {
      FitOptions fo;
      fo.inference = false;
      fo.omega = OmegaKind::kModel;  // as `gmwm fit` weighs by default
      const FitResult r = fit_gmwm(wv, c.baseline, fo);
      if (r.status == FitStatus::kFailed)
        throw InputError("--fit '" + f->spec.text() + "': the fit failed on column '" + c.name + "'");
      c.baseline = r.model;
      c.theta = r.theta;
      c.conversions.push_back("baseline fitted on the column: " + r.model.to_string(r.theta));
      continue;
    }
    c.theta = c.baseline.given_values();
    if (config) random_walk_like(c.baseline, c.theta, c.wv.n, c.conversions);
    if (o.unit_check) check_baseline_units(set.path, c.name, wv, c.baseline, c.theta, o.sensor, o.units);
  }
}

// A gap band within the scales a column's held or interpolated samples smooth is theirs,
// not the sensor's (issue 47, item 2): with the first level auto (the default) those scales
// are not compared; compared on request (a lower first level), such a band is said to be
// the repetition's in the headline and first among the notes, so that no face reads an
// effect named for it as the sensor's.
void say_repetition(const io::Signal& s, const io::SignalSet& set, gap::GapResult& r) {
  if (!s.repeated.detected() || s.repeated.first_clean_level <= 1) return;
  const double clean_tau = std::ldexp(1.0, s.repeated.first_clean_level);
  bool within = false;
  for (const gap::GapBand& b : r.bands) within = within || b.tau_from < clean_tau;
  if (!within) return;
  const std::string kind = s.repeated.held() ? "held" : "interpolated";
  const std::string levels = s.repeated.first_clean_level > 2
                                 ? "levels 1-" + std::to_string(s.repeated.first_clean_level - 1)
                                 : std::string("level 1");
  const std::string note = "the gap below tau = " + significant(clean_tau, 6) + " samples" +
                           (set.freq_known ? " (" + significant(clean_tau / set.freq, 3) + " s)" : "") + " (" + levels +
                           ") is where " + kind +
                           " samples smooth the WV: the repetition's, not the sensor's; an effect named for it there "
                           "is not the sensor's (the first level auto, the default, compares above them)";
  r.notes.insert(r.notes.begin(), note);
  r.headline += "; " + note;
}

// Stage 5: each column diagnosed against its baseline (gap::diagnose_gap). Every column
// draws its reference from the same streams (the seed): a column's diagnosis is the one
// it gets alone, whichever columns come with it, and columns with the same baseline and
// length (a config's three axes of a kind) share one reference, simulated once.
void diagnose_columns(const io::SignalSet& set, const std::vector<double>& temperature, const GapStudyOptions& o,
                      const ProcessContext& ctx, const std::vector<detail::FittedLevels>& levels, GapStudy& study) {
  gap::GapOptions g = o.gap;
  g.refit_baseline = std::holds_alternative<FitBaseline>(o.baseline);
  g.context = ctx;
  g.missing = set.missing;
  if (!g.references) g.references = gap::make_reference_cache();
  const std::size_t K = study.columns.size();
  const double per_column = 2.0 * o.gap.replicates;  // the reference replicates, then the attribution
  for (std::size_t k = 0; k < K; ++k) {
    gap::GapOptions gk = g;
    if (o.progress)
      gk.progress = [&, k](int done, int) { o.progress(static_cast<double>(k) * per_column + done, K * per_column); };
    GapColumnStudy& c = study.columns[k];
    gk.unit = c.unit;
    // The time-domain stage reads the series as a vector: a series in a file is copied.
    const Samples& x = set.signals[k].values;
    const std::vector<double> copy = x.vector() ? std::vector<double>() : x.to_vector();
    const WaveletVariance wv = compared(c.wv, levels[k]), robust_wv = compared(c.robust_wv, levels[k]);
    c.result = gap::diagnose_gap(wv, c.baseline, c.theta, gk, &robust_wv, x.vector() ? x.vector() : &copy,
                                 temperature.empty() ? nullptr : &temperature);
    if (!levels[k].reason.empty()) {  // said where the verdict is read, as say_repetition does
      c.result.notes.insert(c.result.notes.begin(), levels[k].reason);
      c.result.headline += "; " + levels[k].reason;
    }
    say_repetition(set.signals[k], set, c.result);
    if (!set.missing.empty() && K > 1)
      c.result.notes.push_back("the cross-axis correlation reads a regular series: not computed on this record");
    if (o.progress) o.progress(static_cast<double>(k + 1) * per_column, K * per_column);
  }
}

}  // namespace

std::optional<ColumnBaseline> config_baseline(const io::SimConfig& config, io::SensorKind kind,
                                              const std::string& column, std::int64_t n) {
  auto sb = io::baseline_for_column(config, kind, column);
  if (!sb) return std::nullopt;
  ColumnBaseline b{std::move(sb->model), {}, std::move(sb->conversions)};
  b.theta = b.model.given_values();
  random_walk_like(b.model, b.theta, n, b.conversions);
  return b;
}

std::string GapStudyOptions::Validate() const {
  if (std::string why = gap.Validate(); !why.empty()) return why;
  if (gap.estimator || gap.refit_baseline || gap.progress || !gap.unit.empty() || gap.context.freq_known ||
      !gap.missing.empty())
    return "leave gap.estimator, refit_baseline, context, unit, progress and missing unset: the study sets them per "
           "column";
  if (std::string why = wv.Validate(); !why.empty()) return why;
  if (std::string why = first_level_problem(first_level); !why.empty()) return why;
  const ModelSpec* spec = std::holds_alternative<ModelBaseline>(baseline) ? &std::get<ModelBaseline>(baseline).spec
                          : std::holds_alternative<FitBaseline>(baseline) ? &std::get<FitBaseline>(baseline).spec
                                                                          : nullptr;
  if (spec && spec->empty()) return "the baseline's model is empty";
  return {};
}

GapStudy study_gap(io::SignalSet& set, const GapStudyOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError("gap: " + why);
  // A record with gaps is diagnosed from the windows without one (GapOptions::missing);
  // a temperature coupling and the cross-axis correlation read a regular series.
  if (!options.temperature_column.empty()) detail::require_regular(set, "--temperature");
  detail::check_simulated_grid(set, "gap diagnosis");
  const std::vector<double> temperature = take_temperature(set, options.temperature_column);
  const ProcessContext ctx{set.freq, set.freq_known};
  Baselines b = resolve_baselines(set, options, ctx);

  GapStudy study;
  study.baseline_source = b.source;
  study.temperature_column = temperature.empty() ? std::string() : options.temperature_column;
  study.replicates = options.gap.replicates;
  study.seed = options.gap.seed;
  const auto wv_start = std::chrono::steady_clock::now();
  std::vector<WaveletVariance> wvs, robust_wvs;
  wavelet_variances(set, options.wv, wvs, robust_wvs);
  study.wv_seconds = seconds_since(wv_start);
  const bool config = std::holds_alternative<ConfigBaseline>(options.baseline);
  for (std::size_t k = 0; k < set.signals.size(); ++k) {
    GapColumnStudy c;
    c.name = set.signals[k].name;
    if (options.units_declared || config) c.unit = io::unit_of_column(options.units, options.sensor, c.name);
    c.baseline = std::move(b.models[k]);
    c.conversions = std::move(b.conversions[k]);
    c.wv = std::move(wvs[k]);
    c.robust_wv = std::move(robust_wvs[k]);
    study.columns.push_back(std::move(c));
  }
  std::vector<detail::FittedLevels> levels;
  for (std::size_t k = 0; k < study.columns.size(); ++k)
    levels.push_back(detail::fitted_level(set, k, study.columns[k].wv, study.columns[k].baseline, options.first_level,
                                          detail::LevelUse::kCompared));
  baseline_values(set, options, levels, study);

  const auto gap_start = std::chrono::steady_clock::now();
  diagnose_columns(set, temperature, options, ctx, levels, study);
  study.gap_seconds = seconds_since(gap_start);

  // Cross-axis wavelet correlation (docs/gap.md, method note 2) when several columns are given.
  std::vector<std::span<const double>> spans;
  for (const auto& s : set.signals) spans.emplace_back(s.values);
  if (set.missing.empty()) study.cross_axis = gap::cross_axis_correlation(spans, options.wv.levels, options.gap.alpha);
  return study;
}

}  // namespace gmwm::pipeline
