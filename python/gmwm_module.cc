// The Python module `gmwm` (pybind11): the library's wavelet variance, GMWM fit, model
// selection and simulation on numpy arrays. Each result is the plain-Python form of the
// JSON column the command-line program writes for the same data and options (built by the
// same io/ functions, so the numbers are equal to the last bit). The GIL is released while
// the library computes; the library's InputError becomes gmwm.InputError (a ValueError)
// with the same one-line message. Ctrl-C stops a long fit, select or gap within about a
// second with KeyboardInterrupt (run_cancellable below).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "gmwm/engine/check.h"
#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/noise_figures.h"
#include "gmwm/engine/random.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/report/json_output.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/io/sim_config.h"
#include "gmwm/io/units.h"
#include "gmwm/io/fleet_manifest.h"
#include "gmwm/pipeline/export_study.h"
#include "gmwm/pipeline/fleet_study.h"
#include "gmwm/report/fleet_output.h"
#include "gmwm/pipeline/fit_study.h"
#include "gmwm/pipeline/replicate_study.h"
#include "gmwm/io/export.h"
#include "gmwm/report/export_output.h"
#include "gmwm/gap/gap_check.h"
#include "gmwm/pipeline/gap_study.h"
#include "gmwm/pipeline/nav_study.h"
#include "gmwm/pipeline/plan_study.h"
#include "gmwm/report/plan_output.h"
#include "gmwm/report/nav_output.h"
#include "gmwm/pipeline/select_study.h"
#include "gmwm/robust/robust_wv.h"
#include "gmwm/robust/tuning.h"
#include "gmwm/selection/select.h"
#include "gmwm/version.h"

namespace py = pybind11;

namespace {

using gmwm::report::Json;

// A JSON document as the text the CLI writes (report::dump_json: the same renderer, floats
// with 17 significant digits); the Python package builds its typed results from it and
// keeps it for to_json().
std::string to_python(const Json& j) { return gmwm::report::dump_json(j); }

// How often the interpreter's main thread looks for a signal while the library computes
// (Ctrl-C): often enough that KeyboardInterrupt comes well within a second, rarely enough
// that taking the GIL costs nothing next to the work.
constexpr auto kSignalCheckInterval = std::chrono::milliseconds(50);

// A study that Ctrl-C can stop. Python runs its signal handlers only on the main thread
// and only when that thread calls PyErr_CheckSignals, while the library's progress
// callbacks come from TBB's worker threads. So the study runs on a thread of its own (the
// GIL released) and this thread, every kSignalCheckInterval, takes the GIL briefly and
// calls PyErr_CheckSignals. When a handler raises (KeyboardInterrupt), `cancel` is set; the
// progress callbacks the study was given (cancellation_point) then throw gmwm::Cancelled
// at their next call, which unwinds the study's parallel loops, and the handler's
// exception is raised here. `study(progress)` gets that progress callback to install.
template <class Study>
auto run_cancellable(Study&& study) -> decltype(study(std::function<void(int, int)>())) {
  using Result = decltype(study(std::function<void(int, int)>()));
  auto cancel = std::make_shared<std::atomic<bool>>(false);
  const std::function<void(int, int)> cancellation_point = [cancel](int, int) {
    if (cancel->load(std::memory_order_relaxed)) throw gmwm::Cancelled();
  };
  bool interrupted = false;
  std::future<Result> done;
  {
    py::gil_scoped_release release;
    done = std::async(std::launch::async, [&] { return study(cancellation_point); });
    while (done.wait_for(kSignalCheckInterval) != std::future_status::ready) {
      py::gil_scoped_acquire acquire;
      if (PyErr_CheckSignals() != 0) {
        // The handler's exception stays set on this thread while the study winds down.
        interrupted = true;
        cancel->store(true);
        break;
      }
    }
    done.wait();
  }
  if (interrupted) {
    try {
      done.get();  // gmwm::Cancelled, or a result that came first: either way, interrupted
    } catch (...) {
    }
    throw py::error_already_set();
  }
  return done.get();
}

// A 1-D float64 view of one series (copied when not contiguous float64).
std::vector<double> series_of(const py::handle& obj, const char* what) {
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(obj);
  if (!a) {
    PyErr_Clear();  // ensure() leaves the conversion's error set
    throw gmwm::InputError(std::string(what) + ": expected a 1-D array of numbers");
  }
  if (a.ndim() != 1)
    throw gmwm::InputError(std::string(what) + ": expected a 1-D array, got " + std::to_string(a.ndim()) +
                           " dimensions");
  if (a.size() < gmwm::io::kMinSamples)
    throw gmwm::InputError(std::string(what) + ": found " + std::to_string(a.size()) + " samples, expected at least " +
                           std::to_string(gmwm::io::kMinSamples) +
                           " (the wavelet variance needs 4 levels, 2^4 samples)");
  std::vector<double> x(a.data(), a.data() + a.size());
  for (std::size_t i = 0; i < x.size(); ++i)
    if (!std::isfinite(x[i]))
      throw gmwm::InputError(std::string(what) + ": sample " + std::to_string(i) + " is not a finite number");
  // As the CLI's reader: a constant has a wavelet variance of zero, nothing to fit.
  if (std::all_of(x.begin(), x.end(), [&](double v) { return v == x.front(); })) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", x.front());
    throw gmwm::InputError(std::string(what) + ": found all " + std::to_string(x.size()) + " values equal to " + buf +
                           ", expected a varying signal (a constant has a wavelet variance of zero)");
  }
  return x;
}

// The library's check that a WV can be used (underflow, overflow), naming the column.
void check_wv_range(const std::string& name, const gmwm::WaveletVariance& wv, std::span<const double> x) {
  if (const std::string why = gmwm::wv_range_problem(wv, x, false); !why.empty())
    throw gmwm::InputError("column '" + name + "': " + why);
}

// Columns: a 1-D array (one column), a 2-D array (samples x columns, as a file's columns)
// or a sequence of 1-D arrays.
std::vector<std::vector<double>> columns_of(const py::handle& obj) {
  if (py::isinstance<py::array>(obj) && py::cast<py::array>(obj).ndim() == 2) {
    auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(obj);
    if (!a) {
      PyErr_Clear();
      throw gmwm::InputError("data: expected a 2-D array of numbers (samples x columns)");
    }
    if (a.shape(1) == 0) throw gmwm::InputError("data: found no column, expected samples x columns");
    std::vector<std::vector<double>> out(static_cast<std::size_t>(a.shape(1)));
    for (py::ssize_t c = 0; c < a.shape(1); ++c) {
      py::object col = py::reinterpret_steal<py::object>(
          PyObject_GetItem(a.ptr(), py::make_tuple(py::slice(py::none(), py::none(), py::none()), c).ptr()));
      out[static_cast<std::size_t>(c)] = series_of(col, ("column " + std::to_string(c + 1)).c_str());
    }
    return out;
  }
  if (py::isinstance<py::array>(obj)) return {series_of(obj, "data")};
  if (!py::isinstance<py::sequence>(obj) || py::isinstance<py::str>(obj))
    throw gmwm::InputError("data: expected an array (samples, or samples x columns) or a list of 1-D arrays");
  std::vector<std::vector<double>> out;
  std::size_t k = 0;
  for (const auto& item : py::cast<py::sequence>(obj))
    out.push_back(series_of(item, ("column " + std::to_string(++k)).c_str()));
  if (out.empty()) throw gmwm::InputError("data: found no column, expected samples x columns");
  return out;
}

gmwm::report::ColumnInfo info(const std::string& name, std::size_t n, std::optional<double> freq,
                              const std::string& unit) {
  if (freq)
    if (const std::string why = gmwm::io::sampling_rate_problem(*freq, "freq"); !why.empty())
      throw gmwm::InputError(why);
  return {name, static_cast<std::int64_t>(n), freq.value_or(1.0), freq.has_value(), unit};
}

std::vector<std::string> names_for(std::size_t k, const std::vector<std::string>& names) {
  if (names.empty()) {
    std::vector<std::string> out;
    for (std::size_t i = 0; i < k; ++i) out.push_back("x" + std::to_string(i + 1));
    return out;
  }
  if (names.size() != k)
    throw gmwm::InputError("names: " + std::to_string(names.size()) + " names for " + std::to_string(k) + " columns");
  return names;
}

// The columns as the signal set a file would give ("<array>", the rate when known).
gmwm::io::SignalSet signal_set_of(std::vector<std::vector<double>> cols, const std::vector<std::string>& labels,
                                  std::optional<double> freq) {
  const gmwm::report::ColumnInfo first = info(labels.front(), cols.front().size(), freq, "");
  gmwm::io::SignalSet set;
  set.path = "<array>";
  set.freq = first.freq;
  set.freq_known = first.freq_known;
  for (std::size_t k = 0; k < cols.size(); ++k) set.signals.push_back({labels[k], std::move(cols[k]), ""});
  return set;
}

// The robust WV settings of `--robust [--eff E] [--estimator NAME]`; nullopt when not robust.
std::optional<gmwm::robust::RobustWvOptions> robust_options(bool robust, std::optional<double> eff,
                                                            const std::optional<std::string>& estimator, double alpha) {
  if (!robust) {
    if (eff) throw gmwm::InputError("eff: only meaningful with robust=True");
    if (estimator) throw gmwm::InputError("estimator: only meaningful with robust=True");
    return std::nullopt;
  }
  gmwm::robust::RobustWvOptions o;
  o.alpha = alpha;
  if (eff) {
    if (!(*eff > 0.0 && *eff < 1.0))
      throw gmwm::InputError("eff: expected a Gaussian efficiency strictly between 0 and 1 (e.g. 0.6), got " +
                             std::to_string(*eff));
    o.efficiency = *eff;
  }
  if (estimator) {
    const auto kind = gmwm::robust::parse_robust_kind(*estimator);
    if (!kind)
      throw gmwm::InputError("estimator: unknown robust estimator '" + *estimator + "'; expected huber or bisquare");
    o.estimator = *kind;
  }
  if (const std::string why = o.Validate(); !why.empty()) throw gmwm::InputError("robust: " + why);
  return o;
}

gmwm::OmegaKind omega_kind(const std::string& s) {
  if (const auto k = gmwm::parse_omega_kind(s)) return *k;
  throw gmwm::InputError("omega: expected model, diag, full or bootstrap, got '" + s + "'");
}

std::string py_wv(const py::object& data, std::optional<double> freq, double alpha, int levels,
                  const std::string& name) {
  const std::vector<double> x = series_of(data, "data");
  const gmwm::report::ColumnInfo column = info(name, x.size(), freq, "");
  gmwm::WvOptions o;
  o.alpha = alpha;
  o.levels = levels;
  if (const std::string why = o.Validate(); !why.empty()) throw gmwm::InputError(why);
  if (const std::string why = gmwm::io::levels_problem(levels, static_cast<std::int64_t>(x.size()), "levels");
      !why.empty())
    throw gmwm::InputError(why);
  Json out;
  {
    py::gil_scoped_release release;
    const std::vector<std::span<const double>> series{std::span<const double>(x)};
    const gmwm::WaveletVariance wv = gmwm::classical_wv(series, o).front();
    check_wv_range(name, wv, x);
    out = gmwm::report::wv_column_json(column, wv);
  }
  return to_python(out);
}

// The data's Allan deviation and the noise figures read off it: the 'allan' and
// 'noise_figures' fields `gmwm wv --adev` gives a column (the same engine and io functions).
std::string py_allan(const py::object& data, double freq, int points_per_octave, double alpha, const std::string& units,
                     const std::string& name) {
  const std::vector<double> x = series_of(data, "data");
  const std::string unit = gmwm::io::unit_of_column(gmwm::io::parse_units_spec(units), name);
  if (const std::string why = gmwm::io::sampling_rate_problem(freq, "freq"); !why.empty()) throw gmwm::InputError(why);
  gmwm::AllanOptions allan;
  allan.points_per_octave = points_per_octave;
  allan.alpha = alpha;
  if (const std::string why = allan.Validate(); !why.empty()) throw gmwm::InputError("points_per_octave: " + why);
  Json out;
  {
    py::gil_scoped_release release;
    gmwm::ReadoffOptions readoff;
    readoff.alpha = alpha;
    check_wv_range("data",
                   gmwm::classical_wv(std::vector<std::span<const double>>{std::span<const double>(x)}, {}).front(), x);
    const gmwm::FigureReport r = gmwm::data_figure_report(x, freq, allan, readoff);
    out["unit"] = unit.empty() ? Json(nullptr) : Json(unit);
    out["allan"] = gmwm::report::allan_json(r.adev, {});
    out["noise_figures"] = gmwm::report::noise_figures_json(r.chosen, unit);
  }
  return to_python(out);
}

// The fit study (gmwm::pipeline::study_fit, as `gmwm fit`): the 'fit' JSON column with its
// continuous parameters, Kalman terms, Allan deviations and noise figures.
std::string py_fit(const py::object& data, const std::string& model_spec, std::optional<double> freq,
                   const std::string& omega, double alpha, int replicates, std::uint64_t seed, const std::string& name,
                   bool robust, std::optional<double> eff, const std::optional<std::string>& estimator,
                   const std::string& units) {
  const gmwm::io::SignalSet set = signal_set_of({series_of(data, "data")}, {name}, freq);
  const std::string unit = gmwm::io::unit_of_column(gmwm::io::parse_units_spec(units), name);
  gmwm::pipeline::FitStudyOptions o;
  o.model = model_spec;
  o.fit.omega = omega_kind(omega);
  o.fit.alpha = alpha;
  o.fit.bootstrap_replicates = replicates;
  o.fit.seed = seed;
  o.wv.alpha = alpha;
  o.robust = robust_options(robust, eff, estimator, alpha);
  if (const std::string why = o.Validate(); !why.empty()) throw gmwm::InputError(why);
  gmwm::parse_model(model_spec, gmwm::ProcessContext{set.freq, set.freq_known});  // a bad model: InputError, GIL held
  const Json out = run_cancellable([&](const std::function<void(int, int)>& progress) {
    gmwm::pipeline::FitStudyOptions oc = o;
    oc.fit.progress = progress;  // the bootstrap Omega's draws
    if (oc.robust) oc.robust->progress = progress;
    const gmwm::pipeline::FitStudy study = gmwm::pipeline::study_fit(set, oc);
    return Json(gmwm::report::fit_document(set, study, {unit}, set.freq_known ? set.freq : 0.0)["columns"][0]);
  });
  return to_python(out);
}

// The selection study (gmwm::pipeline::study_select, as `gmwm select --model`): a list of
// 'select' JSON columns with the best fit's continuous parameters, Kalman terms, Allan
// deviations and noise figures.
std::string py_select(const py::object& data, const std::string& model_spec, std::optional<double> freq,
                      const std::string& optimism, const std::string& omega, const std::string& penalty, int replicates,
                      double alpha, std::uint64_t seed, const std::vector<std::string>& names, bool robust,
                      std::optional<double> eff, const std::optional<std::string>& estimator,
                      const std::string& units_spec) {
  std::vector<std::vector<double>> cols = columns_of(data);
  const std::vector<std::string> labels = names_for(cols.size(), names);
  const gmwm::io::UnitsSpec spec = gmwm::io::parse_units_spec(units_spec);
  std::vector<std::string> units;
  for (const std::string& label : labels) units.push_back(gmwm::io::unit_of_column(spec, label));
  const gmwm::io::SignalSet set = signal_set_of(std::move(cols), labels, freq);
  namespace sel = gmwm::selection;
  gmwm::pipeline::SelectStudyOptions o;
  o.models = {model_spec};
  sel::SelectOptions& so = o.select;
  if (const auto m = sel::parse_optimism_method(optimism))
    so.optimism = *m;
  else
    throw gmwm::InputError("optimism: expected analytic, bootstrap or both, got '" + optimism + "'");
  if (const auto w = sel::parse_omega_source(omega))
    so.omega = *w;
  else
    throw gmwm::InputError("omega: expected model, full or data, got '" + omega + "'");
  if (const auto p = sel::parse_penalty(penalty))
    so.penalty = *p;
  else
    throw gmwm::InputError("penalty: expected wvic or bic, got '" + penalty + "'");
  so.bootstrap_replicates = replicates;
  so.seed = seed;
  so.fit.alpha = alpha;
  so.fit.seed = seed;
  o.wv.alpha = alpha;
  o.robust = robust_options(robust, eff, estimator, alpha);
  if (const std::string why = o.Validate(); !why.empty()) throw gmwm::InputError(why);
  gmwm::parse_model(model_spec, gmwm::ProcessContext{set.freq, set.freq_known});  // a bad model: InputError, GIL held
  const Json out = run_cancellable([&](const std::function<void(int, int)>& progress) {
    gmwm::pipeline::SelectStudyOptions oc = o;
    oc.select.progress = progress;  // every fit and bootstrap draw
    if (oc.robust) oc.robust->progress = progress;
    const gmwm::pipeline::SelectStudy study = gmwm::pipeline::study_select(set, oc);
    return Json(gmwm::report::select_document(set, study, units, set.freq_known ? set.freq : 0.0)["columns"]);
  });
  return to_python(out);
}

// The gap study (gmwm::pipeline::study_gap, as `gmwm gap`): the document gmwm gap --json
// writes, its "input" being "<array>".
std::string py_gap(const py::object& data, double freq, const std::optional<std::string>& model,
                   const std::optional<std::string>& fit, const std::optional<std::string>& kalibr,
                   const std::string& kalibr_imu, const std::optional<std::string>& gazebo,
                   const std::optional<std::string>& datasheet, const std::vector<std::string>& names,
                   const std::string& units, const std::optional<std::string>& sensor,
                   const std::optional<std::string>& temperature, int replicates, std::uint64_t seed, double alpha,
                   int levels, bool unit_check, const std::string& effects, double min_effect, int max_steps) {
  if (const std::string why = gmwm::io::sampling_rate_problem(freq, "freq"); !why.empty()) throw gmwm::InputError(why);
  const int given =
      model.has_value() + fit.has_value() + kalibr.has_value() + gazebo.has_value() + datasheet.has_value();
  if (given != 1)
    throw gmwm::InputError(
        "gap: give exactly one baseline: model=SPEC_WITH_VALUES, kalibr=imu.yaml, gazebo=FILE.sdf, "
        "datasheet=FILE.yaml or fit=SPEC");
  std::vector<std::vector<double>> cols = columns_of(data);
  const std::vector<std::string> labels = names_for(cols.size(), names);
  gmwm::io::SignalSet set = signal_set_of(std::move(cols), labels, freq);
  gmwm::pipeline::GapStudyOptions o;
  o.wv.alpha = alpha;
  o.wv.levels = levels;
  if (const std::string why =
          gmwm::io::levels_problem(levels, static_cast<std::int64_t>(set.signals.front().values.size()), "levels");
      !why.empty())
    throw gmwm::InputError(why);
  o.units = gmwm::io::parse_units(units);
  o.units_declared = !units.empty();
  if (sensor) {
    if (*sensor != "gyro" && *sensor != "accel")
      throw gmwm::InputError("sensor: expected gyro or accel, got '" + *sensor + "'");
    o.sensor = *sensor == "gyro" ? gmwm::io::SensorKind::kGyro : gmwm::io::SensorKind::kAccel;
  }
  o.temperature_column = temperature.value_or("");
  o.unit_check = unit_check;
  o.gap.replicates = replicates;
  o.gap.seed = seed;
  o.gap.alpha = alpha;
  o.gap.min_effect = min_effect;
  o.gap.max_steps = max_steps;
  if (!effects.empty()) o.gap.candidates = gmwm::gap::parse_gap_candidates(effects, "effects");
  if (model) o.baseline = gmwm::pipeline::ModelBaseline{*model};
  if (fit) o.baseline = gmwm::pipeline::FitBaseline{*fit};
  if (kalibr)
    o.baseline =
        gmwm::pipeline::ConfigBaseline{gmwm::io::read_kalibr_imu_yaml(*kalibr, freq, o.units, kalibr_imu), *kalibr};
  if (gazebo) o.baseline = gmwm::pipeline::ConfigBaseline{gmwm::io::read_gazebo_sdf(*gazebo, freq, o.units), *gazebo};
  if (datasheet)
    o.baseline = gmwm::pipeline::ConfigBaseline{gmwm::io::read_datasheet_yaml(*datasheet, freq, o.units), *datasheet};
  const std::string baseline_file = kalibr ? *kalibr : gazebo ? *gazebo : datasheet.value_or("");
  const Json out = run_cancellable([&](const std::function<void(int, int)>& progress) {
    gmwm::pipeline::GapStudyOptions oc = o;
    oc.progress = [progress](double, double) { progress(0, 0); };  // every replicate and attribution fit
    const gmwm::pipeline::GapStudy study = gmwm::pipeline::study_gap(set, oc);
    Json doc = gmwm::report::gap_document(set, study);
    // The corrected configuration, as `gmwm gap` writes it (its "content" is the file's text).
    doc["corrected"] = gmwm::report::corrected_config_json(
        gmwm::pipeline::corrected_config(set, study, oc, {o.units, o.sensor, baseline_file}), freq);
    return doc;
  });
  return to_python(out);
}

// The navigation study (gmwm::pipeline::study_nav, as `gmwm nav`): the document gmwm nav
// --json writes (without "run"). Sources as the CLI's --truth / --filter.
std::string py_nav(const std::string& truth, const std::vector<std::string>& filters,
                   const std::vector<std::string>& labels, const std::string& trajectory, double horizon,
                   double fix_rate, double fix_sigma, const std::vector<std::pair<double, double>>& outages,
                   double judge_from, double output_interval, std::optional<double> imu_rate,
                   std::optional<double> rate, const std::string& units, int monte_carlo, std::uint64_t seed) {
  gmwm::pipeline::NavStudyOptions o;
  const auto t = gmwm::nav::parse_trajectory(trajectory);
  if (!t) throw gmwm::InputError("trajectory '" + trajectory + "': expected static, constant-velocity or manoeuvre");
  o.scenario.trajectory = *t;
  o.scenario.horizon = horizon;
  o.scenario.fix_rate = fix_rate;
  o.scenario.fix_sigma = fix_sigma;
  o.scenario.judge_from = judge_from;
  o.scenario.output_interval = output_interval;
  if (imu_rate) o.scenario.imu_rate = *imu_rate;
  for (const auto& [a, b] : outages) o.scenario.outages.push_back({a, b});
  o.truth = gmwm::pipeline::parse_nav_source(truth);
  for (const std::string& f : filters) o.filters.push_back(gmwm::pipeline::parse_nav_source(f));
  o.labels = labels;
  o.rate = rate;
  if (!units.empty()) o.units = gmwm::io::parse_declared_units(units);
  o.monte_carlo_runs = monte_carlo;
  o.seed = seed;
  if (const std::string why = o.Validate(); !why.empty()) throw gmwm::InputError("nav: " + why);
  const Json out = run_cancellable([&](const std::function<void(int, int)>& progress) {
    gmwm::pipeline::NavStudyOptions oc = o;
    oc.progress = [progress](double) {
      progress(0, 0);  // throws gmwm::Cancelled on Ctrl-C
      return true;
    };
    return gmwm::report::nav_document(gmwm::pipeline::study_nav(oc));
  });
  return to_python(out);
}

// The record-length plan (gmwm::pipeline::study_plan, as `gmwm plan`): the document gmwm
// plan --json writes (without "run"), from a result's path or a model with values at freq.
std::string py_plan(const std::optional<std::string>& result, const std::optional<std::string>& model,
                    std::optional<double> freq, const std::string& unit, double precision, double confidence,
                    const std::vector<std::string>& targets, std::optional<double> have,
                    const std::vector<std::string>& columns) {
  gmwm::pipeline::PlanStudyOptions o;
  o.result = result.value_or("");
  o.model = model.value_or("");
  o.freq = freq;
  o.unit = unit;
  o.columns = columns;
  o.plan.precision = precision;
  o.plan.confidence = confidence;
  o.plan.targets = targets;
  o.plan.record_seconds = have.value_or(0.0);
  const Json out = run_cancellable([&](const std::function<void(int, int)>&) {
    return gmwm::report::plan_document(gmwm::pipeline::study_plan(o), o.plan);
  });
  return to_python(out);
}

// The diagnosis' self-check on simulated cases (gmwm::gap::run_gap_check, as `gmwm
// gap-check`): the document gmwm gap-check --json writes. Families and strengths are the
// CLI's comma-separated lists, parsed by the same library functions (the same refusals).
std::string py_gap_check(int cases, std::int64_t n, int replicates, const std::string& strengths,
                         const std::string& families, bool null_side, std::uint64_t seed) {
  gmwm::gap::GapCheckOptions o;
  o.cases = cases;
  o.n = n;
  o.replicates = replicates;
  o.strengths = gmwm::gap::parse_gap_strengths(strengths);
  if (!families.empty()) o.families = gmwm::gap::parse_gap_families(families);
  o.null_side = null_side;
  o.seed = seed;
  if (const std::string why = o.Validate(); !why.empty()) throw gmwm::InputError("gap-check: " + why);
  const Json out = run_cancellable([&](const std::function<void(int, int)>& progress) {
    gmwm::gap::GapCheckOptions oc = o;
    oc.progress = progress;
    return gmwm::report::gap_check_document(o, gmwm::gap::run_gap_check(oc));
  });
  return to_python(out);
}

// Replicates given as arrays: each entry a recording (a 1-D array, a 2-D array samples x
// columns, or a list of 1-D arrays) with the same columns as the first; named
// "replicates[k]" in messages and sources ("replicates[1]:gyro_x").
struct ReplicateArrays {
  gmwm::io::SignalSet primary;
  std::vector<gmwm::pipeline::ReplicateGroup> groups;
};

ReplicateArrays replicate_groups(const py::sequence& recordings, std::optional<double> freq,
                                 const std::vector<std::string>& names) {
  if (recordings.size() < 2)
    throw gmwm::InputError("replicates: expected at least 2 recordings, got " + std::to_string(recordings.size()));
  ReplicateArrays out;
  std::vector<gmwm::pipeline::ReplicateRecording> rest;
  for (std::size_t k = 0; k < recordings.size(); ++k) {
    std::vector<std::vector<double>> cols = columns_of(recordings[k]);
    const std::vector<std::string> labels = names_for(cols.size(), names);
    gmwm::io::SignalSet set = signal_set_of(std::move(cols), labels, freq);
    set.path = "replicates[" + std::to_string(k) + "]";
    if (k == 0)
      out.primary = std::move(set);
    else
      rest.push_back({set.path, std::move(set), false});
  }
  out.groups = gmwm::pipeline::group_replicates(out.primary, "replicates[0]", std::move(rest));
  return out;
}

std::vector<std::string> units_of(const std::vector<gmwm::pipeline::ReplicateGroup>& groups,
                                  const std::string& units_spec) {
  const gmwm::io::UnitsSpec spec = gmwm::io::parse_units_spec(units_spec);
  std::vector<std::string> units;
  for (const auto& g : groups) units.push_back(gmwm::io::unit_of_column(spec, g.axis));
  return units;
}

// The joint fit over replicates (gmwm::pipeline::study_joint_fit, as `gmwm fit --joint`):
// the document gmwm fit --joint --json writes (without "run").
std::string py_fit_joint(const py::sequence& recordings, const std::string& model_spec, std::optional<double> freq,
                         const std::string& omega, double alpha, int test_draws, std::uint64_t seed,
                         const std::vector<std::string>& names, bool robust, std::optional<double> eff,
                         const std::optional<std::string>& estimator, const std::string& units_spec) {
  const ReplicateArrays r = replicate_groups(recordings, freq, names);
  const std::vector<std::string> units = units_of(r.groups, units_spec);
  gmwm::pipeline::JointFitStudyOptions o;
  o.model = model_spec;
  o.fit.omega = omega_kind(omega);  // as fit --joint --omega: model (the default), diag or full
  o.fit.alpha = alpha;
  o.fit.seed = seed;
  o.wv.alpha = alpha;
  o.robust = robust_options(robust, eff, estimator, alpha);
  o.test_draws = test_draws;
  o.seed = seed;
  if (const std::string why = o.Validate(); !why.empty()) throw gmwm::InputError(why);
  const gmwm::ProcessContext context{r.primary.freq, r.primary.freq_known};
  gmwm::parse_model(model_spec, context);  // a bad model: InputError, GIL held
  return to_python(run_cancellable([&](const std::function<void(int, int)>& progress) {
    gmwm::pipeline::JointFitStudyOptions oc = o;
    oc.progress = progress;
    const gmwm::pipeline::JointFitStudy study = gmwm::pipeline::study_joint_fit(r.groups, context, oc);
    return gmwm::report::joint_fit_document(r.primary, r.groups, study, units, context.freq_known ? context.freq : 0.0);
  }));
}

// The selection over replicates (gmwm::pipeline::study_joint_select, as `gmwm select
// --joint`): the document gmwm select --joint --json writes (without "run").
std::string py_select_joint(const py::sequence& recordings, const std::string& model_spec, std::optional<double> freq,
                            const std::string& optimism, double alpha, std::uint64_t seed,
                            const std::vector<std::string>& names, bool robust, std::optional<double> eff,
                            const std::optional<std::string>& estimator, const std::string& units_spec,
                            int test_draws) {
  const ReplicateArrays r = replicate_groups(recordings, freq, names);
  const std::vector<std::string> units = units_of(r.groups, units_spec);
  gmwm::pipeline::JointSelectStudyOptions o;
  o.model = model_spec;
  if (optimism != "replicates" && optimism != "all")
    throw gmwm::InputError(
        "optimism: expected replicates (the cross-validated WVIC) or all (with the joint fit's "
        "analytic and bootstrap WVIC beside it), got '" +
        optimism + "'");
  o.select.select.optimism =
      optimism == "all" ? gmwm::selection::OptimismMethod::kBoth : gmwm::selection::OptimismMethod::kAnalytic;
  o.select.select.seed = seed;
  o.select.select.fit.alpha = alpha;
  o.select.select.fit.seed = seed;
  o.select.seed = seed;
  o.wv.alpha = alpha;
  o.robust = robust_options(robust, eff, estimator, alpha);
  o.recommended_test_draws = test_draws;
  if (const std::string why = o.Validate(); !why.empty()) throw gmwm::InputError(why);
  const gmwm::ProcessContext context{r.primary.freq, r.primary.freq_known};
  gmwm::parse_model(model_spec, context);
  return to_python(run_cancellable([&](const std::function<void(int, int)>& progress) {
    gmwm::pipeline::JointSelectStudyOptions oc = o;
    oc.select.select.progress = progress;
    const gmwm::pipeline::JointSelectStudy study = gmwm::pipeline::study_joint_select(r.groups, context, oc);
    return gmwm::report::joint_select_document(r.primary, r.groups, study, units,
                                               context.freq_known ? context.freq : 0.0);
  }));
}

// The export (gmwm::pipeline::study_export, as `gmwm export RESULT --format F --output
// OUTPUT`) of a fit/select result's JSON text: (the document gmwm export --json writes
// without "run", the file's text, the sidecar's text or None).
std::tuple<std::string, std::string, std::optional<std::string>> py_export(
    const std::string& result, const std::string& format, const std::string& output, const std::string& aggregate,
    double inflate, std::optional<double> rate, const std::string& rostopic, const std::string& units,
    const std::optional<std::string>& sensor, const std::vector<std::string>& columns,
    const std::optional<std::tuple<double, double, double>>& consistent_for, const std::string& source_name) {
  gmwm::pipeline::ExportStudyOptions o;
  const auto f = gmwm::io::parse_export_format(format);
  if (!f)
    throw gmwm::InputError("format '" + format + "': unknown format, expected one of " +
                           gmwm::io::export_format_names());
  o.format.format = *f;
  const auto a = gmwm::io::parse_aggregation(aggregate);
  if (!a) throw gmwm::InputError("aggregate '" + aggregate + "': expected per-axis, mean or worst");
  o.format.aggregation = *a;
  o.format.inflate = inflate;
  o.format.rate = rate;
  o.format.rostopic = rostopic;
  if (consistent_for) {
    gmwm::pipeline::ConsistencyOptions c;
    std::tie(c.update_rate, c.horizon, c.fix_sigma) = *consistent_for;
    o.consistent_for = c;
  }
  if (const std::string why = o.Validate(); !why.empty()) throw gmwm::InputError(why);
  gmwm::io::ResultReadOptions ro;
  ro.columns = columns;
  ro.rate = rate;
  if (sensor) {
    if (*sensor != "gyro" && *sensor != "accel")
      throw gmwm::InputError("sensor: expected gyro or accel, got '" + *sensor + "'");
    ro.sensor = *sensor == "gyro" ? gmwm::io::SensorKind::kGyro : gmwm::io::SensorKind::kAccel;
  }
  if (!units.empty()) ro.units = gmwm::io::parse_declared_units(units);
  // As the CLI names its INPUT: the result file's path when the result came from one.
  const std::string name = source_name.empty() ? std::string("result") : source_name;
  gmwm::io::ResultColumns r = gmwm::io::read_result_columns(name, result, ro);
  const std::string source = "gmwm " + r.command + " result" + (source_name.empty() ? "" : " " + source_name) +
                             (r.input.empty() ? "" : " (data " + r.input + ")");
  const gmwm::pipeline::ExportStudy study = gmwm::pipeline::study_export(r.columns, source, name, o);
  return {to_python(gmwm::report::export_document(study, output)), study.result.content, study.result.sidecar};
}

// The fleet study (gmwm::pipeline::study_fleet, as `gmwm fleet MANIFEST --model SPEC`): the
// document gmwm fleet --json writes (without "run"). The manifest's bad rows are refused up
// front, all of them in one gmwm.InputError (a line each, as the CLI prints them).
std::string py_fleet(const std::string& manifest_path, const std::string& model_spec, double alpha, std::uint64_t seed,
                     std::optional<double> memory_mb) {
  gmwm::pipeline::FleetStudyOptions o;
  o.model = model_spec;
  o.wv.alpha = alpha;
  o.select.fit.alpha = alpha;
  o.select.fit.seed = seed;
  o.select.seed = seed;
  if (memory_mb) o.memory_budget = *memory_mb * 1e6;
  if (const std::string why = o.Validate(); !why.empty()) throw gmwm::InputError("fleet: " + why);
  const gmwm::io::FleetManifest manifest = gmwm::io::read_fleet_manifest(manifest_path);
  if (const std::vector<std::string> problems = gmwm::io::fleet_manifest_problems(manifest); !problems.empty()) {
    std::string all;
    for (const std::string& p : problems) all += (all.empty() ? "" : "\n") + p;
    // Raised as gmwm.InputError directly: the translator would squeeze the lines into one.
    const py::object input_error = py::module_::import("gmwm._gmwm").attr("InputError");
    PyErr_SetString(input_error.ptr(), all.c_str());
    throw py::error_already_set();
  }
  return to_python(run_cancellable([&](const std::function<void(int, int)>& progress) {
    gmwm::pipeline::FleetStudyOptions oc = o;
    oc.progress = progress;  // after each recording
    oc.select.progress = progress;
    return gmwm::report::fleet_document(gmwm::pipeline::study_fleet(manifest, oc));
  }));
}

py::array_t<double> py_simulate(const std::string& model_spec, std::int64_t n, std::uint64_t seed, int signals,
                                std::optional<double> freq) {
  if (n < 1) throw gmwm::InputError("n: expected a positive number of samples, got " + std::to_string(n));
  if (signals < 1) throw gmwm::InputError("signals: expected at least 1, got " + std::to_string(signals));
  if (freq)
    if (const std::string why = gmwm::io::sampling_rate_problem(*freq, "freq"); !why.empty())
      throw gmwm::InputError(why);
  const gmwm::Model model = gmwm::parse_model(model_spec, gmwm::ProcessContext{freq.value_or(1.0), freq.has_value()});
  if (!model.fully_specified())
    throw gmwm::InputError("model '" + model_spec + "': give every parameter a value to simulate");
  const Eigen::VectorXd theta = model.given_values();
  if (const std::string why = model.validate(theta); !why.empty()) throw gmwm::InputError(why);
  // Samples x signals, as a file's columns and as select() takes them.
  py::array_t<double> out(signals == 1 ? std::vector<py::ssize_t>{n} : std::vector<py::ssize_t>{n, signals});
  double* dst = out.mutable_data();
  {
    py::gil_scoped_release release;
    for (int k = 0; k < signals; ++k) {
      const std::vector<double> x = gmwm::simulate(model, theta, n, seed, static_cast<std::uint64_t>(k));
      for (std::int64_t i = 0; i < n; ++i) dst[i * signals + k] = x[static_cast<std::size_t>(i)];
    }
  }
  return out;
}

}  // namespace

PYBIND11_MODULE(_gmwm, m) {
  m.doc() = "gmwm: wavelet variance, GMWM fits and model selection for inertial sensor noise";
  m.attr("__version__") = gmwm::library_version();
  m.attr("DEFAULT_SEED") = gmwm::kDefaultSeed;
  static py::exception<gmwm::InputError> input_error(m, "InputError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const gmwm::InputError& e) {
      input_error(gmwm::printable_line(e.what()).c_str());
    } catch (const gmwm::InvalidArgument& e) {
      input_error(gmwm::capped_line(gmwm::printable_line(e.what()))
                      .c_str());  // the library's argument checks: bad input too, as the CLI's exit 2
    }
  });
  m.def("wv", &py_wv, py::arg("data"), py::kw_only(), py::arg("freq") = py::none(), py::arg("alpha") = 0.05,
        py::arg("levels") = 0, py::arg("name") = "x1",
        "Classical Haar wavelet variance with its chi-square intervals: the 'wv' JSON column");
  m.def("fit", &py_fit, py::arg("data"), py::arg("model"), py::kw_only(), py::arg("freq") = py::none(),
        py::arg("omega") = "model", py::arg("alpha") = 0.05,
        py::arg("replicates") = gmwm::FitOptions{}.bootstrap_replicates, py::arg("seed") = gmwm::kDefaultSeed,
        py::arg("name") = "x1", py::arg("robust") = false, py::arg("eff") = py::none(),
        py::arg("estimator") = py::none(), py::arg("units") = "",
        "GMWM fit of a model (e.g. 'AR1+WN+RW') with inference, to the classical or robust WV: the 'fit' JSON column "
        "(with continuous parameters, Kalman terms, Allan deviations and noise figures in the column's unit; `units` "
        "as the CLI's --units: 'deg/s' or 'gyro=deg/s,accel=g' with the kind from `name`)");
  m.def("select", &py_select, py::arg("data"), py::arg("model"), py::kw_only(), py::arg("freq") = py::none(),
        py::arg("optimism") = "analytic", py::arg("omega") = "model", py::arg("penalty") = "wvic",
        py::arg("replicates") = gmwm::selection::SelectOptions{}.bootstrap_replicates, py::arg("alpha") = 0.05,
        py::arg("seed") = gmwm::kDefaultSeed, py::arg("names") = std::vector<std::string>{}, py::arg("robust") = false,
        py::arg("eff") = py::none(), py::arg("estimator") = py::none(), py::arg("units") = "",
        "Every sub-model of a maximal model ranked by WVIC (or BIC), per column: a list of 'select' JSON columns "
        "(with the best fit's continuous parameters, Kalman terms, Allan deviations and noise figures; `units` as "
        "the CLI's --units: 'deg/s' or 'gyro=deg/s,accel=g' with each column's kind from its name)");
  m.def("allan", &py_allan, py::arg("data"), py::kw_only(), py::arg("freq"),
        py::arg("points_per_octave") = gmwm::AllanOptions{}.points_per_octave, py::arg("alpha") = 0.05,
        py::arg("units") = "", py::arg("name") = "x1",
        "Overlapping Allan deviation with chi-square intervals and the noise figures read off it (N, K, B): "
        "the 'allan' and 'noise_figures' fields of gmwm wv --adev");
  m.def("gap", &py_gap, py::arg("data"), py::kw_only(), py::arg("freq"), py::arg("model") = py::none(),
        py::arg("fit") = py::none(), py::arg("kalibr") = py::none(), py::arg("kalibr_imu") = "",
        py::arg("gazebo") = py::none(), py::arg("datasheet") = py::none(),
        py::arg("names") = std::vector<std::string>{}, py::arg("units") = "", py::arg("sensor") = py::none(),
        py::arg("temperature") = py::none(), py::arg("replicates") = gmwm::gap::GapOptions{}.replicates,
        py::arg("seed") = gmwm::kDefaultSeed, py::arg("alpha") = 0.05, py::arg("levels") = 0,
        py::arg("unit_check") = true, py::arg("effects") = "",
        py::arg("min_effect") = gmwm::gap::GapOptions{}.min_effect,
        py::arg("max_steps") = gmwm::gap::GapOptions{}.max_steps,
        "Sim-to-real gap: where a baseline noise model (model=, fit=, kalibr=, gazebo=, datasheet=) departs from each "
        "column's WV, "
        "which effect explains it and by how much: the document gmwm gap --json writes");
  m.def("nav", &py_nav, py::arg("truth"), py::arg("filters") = std::vector<std::string>{}, py::kw_only(),
        py::arg("labels") = std::vector<std::string>{}, py::arg("trajectory") = "static", py::arg("horizon") = 600.0,
        py::arg("fix_rate") = 1.0, py::arg("fix_sigma") = 1.0,
        py::arg("outages") = std::vector<std::pair<double, double>>{}, py::arg("judge_from") = 0.0,
        py::arg("output_interval") = 1.0, py::arg("imu_rate") = py::none(), py::arg("rate") = py::none(),
        py::arg("units") = "", py::arg("monte_carlo") = 0, py::arg("seed") = gmwm::kDefaultSeed,
        "What a noise model costs a navigation filter: each filter model's errors and NEES against the truth "
        "(sources as gmwm nav's --truth/--filter): the document gmwm nav --json writes");
  m.def("plan", &py_plan, py::arg("result") = py::none(), py::kw_only(), py::arg("model") = py::none(),
        py::arg("freq") = py::none(), py::arg("unit") = "", py::arg("precision") = 0.1, py::arg("confidence") = 0.95,
        py::arg("targets") = std::vector<std::string>{}, py::arg("have") = py::none(),
        py::arg("columns") = std::vector<std::string>{},
        "How long to record: per column of a fit/select result (or for model= at freq=), the record length at which "
        "N, K, B or a parameter reach a precision: the document gmwm plan --json writes");
  m.def("gap_check", &py_gap_check, py::kw_only(), py::arg("cases") = 3, py::arg("n") = std::int64_t{1} << 18,
        py::arg("replicates") = 100, py::arg("strengths") = "2,4,8", py::arg("families") = "", py::arg("null") = true,
        py::arg("seed") = gmwm::kDefaultSeed,
        "The gap diagnosis' self-check on simulated cases with a withheld effect (families 'QN,DR,...', strengths "
        "'2,4,8'): the document gmwm gap-check --json writes");
  m.def("fit_joint", &py_fit_joint, py::arg("replicates"), py::arg("model"), py::kw_only(),
        py::arg("freq") = py::none(), py::arg("omega") = "model", py::arg("alpha") = 0.05,
        py::arg("test_draws") = gmwm::ReplicateTestOptions{}.bootstrap, py::arg("seed") = gmwm::kDefaultSeed,
        py::arg("names") = std::vector<std::string>{}, py::arg("robust") = false, py::arg("eff") = py::none(),
        py::arg("estimator") = py::none(), py::arg("units") = "",
        "Joint (multi-signal) GMWM fit of one model per axis over replicates (recordings of one sensor, each an "
        "array with the same columns): the document gmwm fit --joint --json writes");
  m.def("select_joint", &py_select_joint, py::arg("replicates"), py::arg("model"), py::kw_only(),
        py::arg("freq") = py::none(), py::arg("optimism") = "replicates", py::arg("alpha") = 0.05,
        py::arg("seed") = gmwm::kDefaultSeed, py::arg("names") = std::vector<std::string>{}, py::arg("robust") = false,
        py::arg("eff") = py::none(), py::arg("estimator") = py::none(), py::arg("units") = "",
        py::arg("test_draws") = 0,
        "Selection over replicates (cross-validated WVIC; optimism='all' adds the joint fit's analytic and bootstrap "
        "WVIC): the document gmwm select --joint --json writes");
  m.def("export", &py_export, py::arg("result"), py::kw_only(), py::arg("format"), py::arg("output") = "",
        py::arg("aggregate") = "mean", py::arg("inflate") = 1.0, py::arg("rate") = py::none(),
        py::arg("rostopic") = "/imu0", py::arg("units") = "", py::arg("sensor") = py::none(),
        py::arg("columns") = std::vector<std::string>{}, py::arg("consistent_for") = py::none(),
        py::arg("source_name") = "",
        "A fit/select result's noise parameters (its JSON text) in a consumer's format (kalibr, openvins, vins, "
        "orbslam3, basalt, gz-sdf, rotors): (the document gmwm export --json writes, the file's text, the "
        "sidecar's text or None); consistent_for=(rate Hz, horizon s, update sigma m) derives the inflation");
  m.def("fleet", &py_fleet, py::arg("manifest"), py::kw_only(), py::arg("model"), py::arg("alpha") = 0.05,
        py::arg("seed") = gmwm::kDefaultSeed, py::arg("memory") = py::none(),
        "Every recording of a manifest (CSV or YAML: path, unit, model[, topic, columns, units, rate, group]) "
        "selected over `model` as gmwm select does, one row per unit x axis with N, K, B, the fleet's summary and "
        "the units that stand out: the document gmwm fleet --json writes");
  m.def("simulate", &py_simulate, py::arg("model"), py::arg("n"), py::kw_only(), py::arg("seed") = gmwm::kDefaultSeed,
        py::arg("signals") = 1, py::arg("freq") = py::none(),
        "Independent series of a fully specified model: shape (n,), or (n, signals) with signal k on stream k, "
        "as gmwm simulate's columns");
}
