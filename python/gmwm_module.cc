// The Python module `gmwm._gmwm` (pybind11): the library's wavelet variance, GMWM fit, model
// selection, gap, nav, plan and simulation on numpy arrays (the joint studies, export and
// fleet in multi_signal_bindings.cc). Each function returns the JSON text the command-line
// program writes for the same data and options (the same report:: functions, so the numbers
// are equal to the last bit); python/gmwm builds its typed results from it. The GIL is
// released while the library computes; the library's InputError becomes gmwm.InputError (a
// ValueError) with the same one-line message. Ctrl-C stops a long study within about a second
// with KeyboardInterrupt (run_cancellable, module_support.h).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <functional>
#include <future>
#include <map>
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
#include "gmwm/io/option_wording.h"
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
#include "gmwm/fleet/fleet_study.h"
#include "gmwm/report/fleet_output.h"
#include "gmwm/pipeline/fit_study.h"
#include "gmwm/pipeline/first_level.h"
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
#include "gmwm/pipeline/wv_study.h"
#include "gmwm/robust/robust_wv.h"
#include "gmwm/robust/tuning.h"
#include "gmwm/selection/select.h"
#include "gmwm/version.h"
#include "gmwm/engine/choice.h"

#include "module_support.h"

namespace py = pybind11;

namespace {

using namespace gmwm::python;  // the shared helpers (module_support.h)

// The WV study (gmwm::pipeline::study_wv, as `gmwm wv`): the 'wv' JSON column, classical or
// robust (with the classical WV and the per-level diagnostic beside it), with the Allan
// deviation and its noise figures when `adev` (as --adev).
std::string py_wv(const py::object& data, std::optional<double> freq, double alpha, int levels, const std::string& name,
                  bool robust, std::optional<double> eff, const std::optional<std::string>& estimator,
                  bool spike_screen, const std::string& units, bool adev, int adev_points) {
  const std::vector<double> x = series_of(data, "data");
  const std::string unit = gmwm::io::unit_of_column(gmwm::io::parse_units_spec(units), name);
  const gmwm::io::SignalSet set = signal_set_of({x}, {name}, freq);
  gmwm::pipeline::WvStudyOptions o;
  o.wv.alpha = alpha;
  o.wv.levels = levels;
  if (const std::string why = o.wv.Validate(); !why.empty()) throw gmwm::InputError(why);
  if (const std::string why = gmwm::io::levels_problem(levels, static_cast<std::int64_t>(x.size()), "levels");
      !why.empty())
    throw gmwm::InputError(why);
  o.robust = robust_options(robust, eff, estimator, alpha, levels, spike_screen);
  if (adev) {
    gmwm::AllanOptions allan;
    allan.points_per_octave = adev_points;
    allan.alpha = alpha;
    if (const std::string why = allan.Validate(); !why.empty()) throw gmwm::InputError("--adev-points: " + why);
    o.allan = allan;
  }
  if (const std::string why = o.Validate(); !why.empty()) throw gmwm::InputError(why);
  const Json out = run_cancellable([&](const std::function<void(int, int)>& progress) {
    gmwm::pipeline::WvStudyOptions oc = o;
    if (oc.robust) oc.robust->progress = progress;
    const gmwm::pipeline::WvStudy study = gmwm::pipeline::study_wv(set, oc);
    const gmwm::pipeline::WvColumnStudy& c = study.columns.front();
    check_wv_range(name, c.robust ? c.robust->classical : c.wv, x);
    return Json(gmwm::report::wv_document(set, study, {unit})["columns"][0]);
  });
  return to_python(out);
}

// The data's Allan deviation and the noise figures read off it: the 'allan' and
// 'noise_figures' fields `gmwm wv --adev` gives a column (the same engine and io functions).
std::string py_allan(const py::object& data, std::optional<double> given_freq, int points_per_octave, double alpha,
                     const std::string& units, const std::string& name) {
  const std::vector<double> x = series_of(data, "data");
  const std::string unit = gmwm::io::unit_of_column(gmwm::io::parse_units_spec(units), name);
  const double freq = given_rate(given_freq);
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

// max_evaluations='s default, the fit's.
const int kMaxEvaluations = gmwm::FitOptions{}.max_evaluations;

// The fit study (gmwm::pipeline::study_fit, as `gmwm fit`): the 'fit' JSON column with its
// continuous parameters, Kalman terms, Allan deviations and noise figures.
std::string py_fit(const py::object& data, const std::string& model_spec, std::optional<double> freq,
                   const std::string& omega, double alpha, int replicates, std::uint64_t seed, const std::string& name,
                   bool robust, std::optional<double> eff, const std::optional<std::string>& estimator,
                   bool spike_screen, const std::string& units, int levels, int max_evaluations,
                   std::optional<double> kf_rate, const py::object& first_level) {
  const int first = first_level_argument(first_level);
  const gmwm::io::SignalSet set = signal_set_of({series_of(data, "data")}, {name}, freq);
  const std::string unit = gmwm::io::unit_of_column(gmwm::io::parse_units_spec(units), name);
  const double filter = kalman_rate(kf_rate, set);
  gmwm::pipeline::FitStudyOptions o;
  o.model = model_spec;
  o.fit.omega = omega_kind(omega);
  o.fit.alpha = alpha;
  o.fit.bootstrap_replicates = replicates;
  o.fit.seed = seed;
  o.fit.max_evaluations = max_evaluations;
  o.wv = wv_levels(alpha, levels, set);
  o.robust = robust_options(robust, eff, estimator, alpha, levels, spike_screen);
  o.first_level = first;
  if (const std::string why = o.Validate(); !why.empty()) throw gmwm::InputError(why);
  gmwm::parse_model(model_spec, gmwm::ProcessContext{set.freq, set.freq_known});  // a bad model: InputError, GIL held
  const Json out = run_cancellable([&](const std::function<void(int, int)>& progress) {
    gmwm::pipeline::FitStudyOptions oc = o;
    oc.fit.progress = progress;  // the bootstrap Omega's draws
    if (oc.robust) oc.robust->progress = progress;
    const gmwm::pipeline::FitStudy study = gmwm::pipeline::study_fit(set, oc);
    return Json(gmwm::report::fit_document(set, study, {unit}, filter)["columns"][0]);
  });
  return to_python(out);
}

// The selection study (gmwm::pipeline::study_select, as `gmwm select --model`): a list of
// 'select' JSON columns with the best fit's continuous parameters, Kalman terms, Allan
// deviations and noise figures.
std::string py_select(const py::object& data, const std::string& model_spec, std::optional<double> freq,
                      const std::string& optimism, const std::string& omega, const std::string& penalty, int replicates,
                      double alpha, std::uint64_t seed, const std::vector<std::string>& names, bool robust,
                      std::optional<double> eff, const std::optional<std::string>& estimator, bool spike_screen,
                      const std::string& units_spec, const std::string& models, int levels, int max_evaluations,
                      std::optional<double> kf_rate, const py::object& first_level) {
  const int first = first_level_argument(first_level);
  std::vector<std::string> found;
  std::vector<std::vector<double>> cols = columns_of(data, &found);
  const std::vector<std::string> labels = names_for(cols.size(), names, found);
  const gmwm::io::UnitsSpec spec = gmwm::io::parse_units_spec(units_spec);
  std::vector<std::string> units;
  for (const std::string& label : labels) units.push_back(gmwm::io::unit_of_column(spec, label));
  const gmwm::io::SignalSet set = signal_set_of(std::move(cols), labels, freq);
  const double filter = kalman_rate(kf_rate, set);
  namespace sel = gmwm::selection;
  gmwm::pipeline::SelectStudyOptions o;
  gmwm::pipeline::set_select_models(o, model_spec, models);
  sel::SelectOptions& so = o.select;
  if (const auto m = sel::parse_optimism_method(optimism))
    so.optimism = *m;
  else
    throw gmwm::InputError("--optimism: " + gmwm::unknown_choice(optimism, sel::optimism_method_names()));
  if (const auto w = sel::parse_omega_source(omega))
    so.omega = *w;
  else
    throw gmwm::InputError("--omega: " + gmwm::unknown_choice(omega, sel::omega_source_names()));
  if (const auto p = sel::parse_penalty(penalty))
    so.penalty = *p;
  else
    throw gmwm::InputError("--penalty: " + gmwm::unknown_choice(penalty, sel::penalty_names()));
  so.bootstrap_replicates = replicates;
  so.seed = seed;
  so.fit.alpha = alpha;
  so.fit.seed = seed;
  so.fit.max_evaluations = max_evaluations;
  o.wv = wv_levels(alpha, levels, set);
  o.robust = robust_options(robust, eff, estimator, alpha, levels, spike_screen);
  o.first_level = first;
  if (const std::string why = o.Validate(); !why.empty()) throw gmwm::InputError(why);
  for (const gmwm::ModelSpec& listed : o.models)  // a bad model: InputError, GIL held
    listed.bind(gmwm::ProcessContext{set.freq, set.freq_known});
  const Json out = run_cancellable([&](const std::function<void(int, int)>& progress) {
    gmwm::pipeline::SelectStudyOptions oc = o;
    oc.select.progress = progress;  // every fit and bootstrap draw
    if (oc.robust) oc.robust->progress = progress;
    const gmwm::pipeline::SelectStudy study = gmwm::pipeline::study_select(set, oc);
    return Json(gmwm::report::select_document(set, study, units, filter)["columns"]);
  });
  return to_python(out);
}

// The gap study (gmwm::pipeline::study_gap, as `gmwm gap`): the document gmwm gap --json
// writes, its "input" being "<array>".
std::string py_gap(const py::object& data, std::optional<double> given_freq, const std::optional<std::string>& model,
                   const std::optional<std::string>& fit, const std::optional<std::string>& kalibr,
                   const std::string& kalibr_imu, const std::optional<std::string>& gazebo,
                   const std::optional<std::string>& datasheet, const std::vector<std::string>& names,
                   const std::string& units, const std::optional<std::string>& sensor,
                   const std::optional<std::string>& temperature, int replicates, std::uint64_t seed, double alpha,
                   int levels, bool unit_check, const std::string& effects, double min_effect, int max_steps,
                   const py::object& first_level) {
  const int first = first_level_argument(first_level);
  const double freq = given_rate(given_freq);
  const int given =
      model.has_value() + fit.has_value() + kalibr.has_value() + gazebo.has_value() + datasheet.has_value();
  if (given != 1)
    throw gmwm::InputError(
        "gap: give exactly one baseline: model=SPEC_WITH_VALUES, kalibr=imu.yaml, gazebo=FILE.sdf, "
        "datasheet=FILE.yaml or fit=SPEC");
  std::vector<std::string> found;
  std::vector<std::vector<double>> cols = columns_of(data, &found);
  const std::vector<std::string> labels = names_for(cols.size(), names, found);
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
    const auto kind = gmwm::io::parse_sensor_kind(*sensor);
    if (!kind) throw gmwm::InputError("--sensor: " + gmwm::unknown_choice(*sensor, gmwm::io::sensor_kind_names()));
    o.sensor = *kind;
  }
  o.temperature_column = temperature.value_or("");
  o.unit_check = unit_check;
  o.first_level = first;
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
  if (!t) throw gmwm::InputError("--trajectory: " + gmwm::unknown_choice(trajectory, gmwm::nav::trajectory_names()));
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
// plan --json writes (without "run"), from a result's JSON text or a model with values at freq.
std::string py_plan(const std::optional<std::string>& result, const std::optional<std::string>& model,
                    std::optional<double> freq, const std::string& unit, double precision, double confidence,
                    const std::vector<std::string>& targets, std::optional<double> have,
                    const std::vector<std::string>& columns, const std::string& source_name) {
  gmwm::pipeline::PlanStudyOptions o;
  o.result_text = result.value_or("");
  o.result = source_name;
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

// The WV a fully specified model implies at `tau` (samples), component by component: each
// component's label (its process, numbered when the model repeats it) and a components x
// levels array whose column sums are the model's WV (the plots' decomposition of a fit).
std::tuple<std::vector<std::string>, py::array_t<double>> py_model_wv(
    const std::string& model_spec, const py::array_t<double, py::array::c_style | py::array::forcecast>& tau,
    std::optional<double> freq) {
  if (tau.ndim() != 1) throw gmwm::InputError("tau: expected a 1-D array of scales in samples");
  const gmwm::Model model = gmwm::parse_model(model_spec, gmwm::ProcessContext{freq.value_or(1.0), freq.has_value()});
  if (!model.fully_specified())
    throw gmwm::InputError("model '" + model_spec + "': give every parameter a value (a fit's model has them)");
  const Eigen::VectorXd theta = model.given_values();
  if (const std::string why = model.validate(theta); !why.empty()) throw gmwm::InputError(why);
  const std::span<const double> scales(tau.data(), static_cast<std::size_t>(tau.size()));
  const auto k = static_cast<py::ssize_t>(model.num_components());
  py::array_t<double> out(std::vector<py::ssize_t>{k, static_cast<py::ssize_t>(scales.size())});
  std::vector<std::string> labels;
  std::map<std::string, int> seen, count;
  for (const gmwm::Component& c : model.components()) ++count[c.process->name()];
  for (py::ssize_t c = 0; c < k; ++c) {
    const gmwm::Component& component = model.components()[static_cast<std::size_t>(c)];
    const std::string name = component.process->name();
    labels.push_back(count[name] > 1 ? name + " " + std::to_string(++seen[name]) : name);
    const gmwm::Model alone({component});
    const Eigen::VectorXd wv = alone.wv(alone.given_values(), scales);
    std::copy(wv.data(), wv.data() + wv.size(), out.mutable_data(c, 0));
  }
  return {labels, out};
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
      // In Python's words: the keyword arguments that set what the message names as CLI options.
      input_error(gmwm::io::option_wording(gmwm::printable_line(e.what()), gmwm::io::Face::kPython).c_str());
    } catch (const gmwm::InvalidArgument& e) {
      // The library's argument checks: bad input too, as the CLI's exit 2.
      input_error(
          gmwm::io::option_wording(gmwm::capped_line(gmwm::printable_line(e.what())), gmwm::io::Face::kPython).c_str());
    }
  });
  m.def("wv", &py_wv, py::arg("data"), py::kw_only(), py::arg("freq") = py::none(), py::arg("alpha") = 0.05,
        py::arg("levels") = 0, py::arg("name") = "x1", py::arg("robust") = false, py::arg("eff") = py::none(),
        py::arg("estimator") = py::none(), py::arg("spike_screen") = true, py::arg("units") = "",
        py::arg("adev") = false, py::arg("adev_points") = gmwm::AllanOptions{}.points_per_octave,
        "Haar wavelet variance with its intervals, as gmwm wv: the 'wv' JSON column; classical, or robust "
        "(robust=True: Huber's Proposal 2, the classical WV and a per-level contamination diagnostic beside it); "
        "adev=True adds the overlapping Allan deviation and the N, K, B read-offs in the column's unit (`units` as "
        "the CLI's --units)");
  m.def("fit", &py_fit, py::arg("data"), py::arg("model"), py::kw_only(), py::arg("freq") = py::none(),
        py::arg("omega") = "model", py::arg("alpha") = 0.05,
        py::arg("replicates") = gmwm::FitOptions{}.bootstrap_replicates, py::arg("seed") = gmwm::kDefaultSeed,
        py::arg("name") = "x1", py::arg("robust") = false, py::arg("eff") = py::none(),
        py::arg("estimator") = py::none(), py::arg("spike_screen") = true, py::arg("units") = "", py::arg("levels") = 0,
        py::arg("max_evaluations") = kMaxEvaluations, py::arg("kf_rate") = py::none(), py::arg("first_level") = 1,
        "GMWM fit of a model (e.g. 'AR1+WN+RW') with inference, to the classical or robust WV: the 'fit' JSON column "
        "(with continuous parameters, Kalman terms, Allan deviations and noise figures in the column's unit; `units` "
        "as the CLI's --units: 'deg/s' or 'gyro=deg/s,accel=g' with the kind from `name`; `first_level` as the CLI's "
        "--first-level: the first level fitted, or 'auto' above the scales held or interpolated samples smooth)");
  m.def("select", &py_select, py::arg("data"), py::arg("model") = "", py::kw_only(), py::arg("freq") = py::none(),
        py::arg("optimism") = "analytic", py::arg("omega") = "model", py::arg("penalty") = "wvic",
        py::arg("replicates") = gmwm::selection::SelectOptions{}.bootstrap_replicates, py::arg("alpha") = 0.05,
        py::arg("seed") = gmwm::kDefaultSeed, py::arg("names") = std::vector<std::string>{}, py::arg("robust") = false,
        py::arg("eff") = py::none(), py::arg("estimator") = py::none(), py::arg("spike_screen") = true,
        py::arg("units") = "", py::arg("models") = "", py::arg("levels") = 0,
        py::arg("max_evaluations") = kMaxEvaluations, py::arg("kf_rate") = py::none(), py::arg("first_level") = 1,
        "Every sub-model of a maximal model (or, models='SPEC1;SPEC2;...', the listed models) ranked by WVIC (or "
        "BIC), per column: a list of 'select' JSON columns "
        "(with the best fit's continuous parameters, Kalman terms, Allan deviations and noise figures; `units` as "
        "the CLI's --units: 'deg/s' or 'gyro=deg/s,accel=g' with each column's kind from its name; `first_level` as "
        "the CLI's --first-level)");
  m.def("allan", &py_allan, py::arg("data"), py::kw_only(), py::arg("freq") = py::none(),
        py::arg("points_per_octave") = gmwm::AllanOptions{}.points_per_octave, py::arg("alpha") = 0.05,
        py::arg("units") = "", py::arg("name") = "x1",
        "Overlapping Allan deviation with chi-square intervals and the noise figures read off it (N, K, B): "
        "the 'allan' and 'noise_figures' fields of gmwm wv --adev");
  m.def("gap", &py_gap, py::arg("data"), py::kw_only(), py::arg("freq") = py::none(), py::arg("model") = py::none(),
        py::arg("fit") = py::none(), py::arg("kalibr") = py::none(), py::arg("kalibr_imu") = "",
        py::arg("gazebo") = py::none(), py::arg("datasheet") = py::none(),
        py::arg("names") = std::vector<std::string>{}, py::arg("units") = "", py::arg("sensor") = py::none(),
        py::arg("temperature") = py::none(), py::arg("replicates") = gmwm::gap::GapOptions{}.replicates,
        py::arg("seed") = gmwm::kDefaultSeed, py::arg("alpha") = 0.05, py::arg("levels") = 0,
        py::arg("unit_check") = true, py::arg("effects") = "",
        py::arg("min_effect") = gmwm::gap::GapOptions{}.min_effect,
        py::arg("max_steps") = gmwm::gap::GapOptions{}.max_steps, py::arg("first_level") = "auto",
        "Sim-to-real gap: where a baseline (model=, fit=, kalibr=, gazebo=, datasheet=) departs from each column's "
        "WV, which effect explains it, by how much (gmwm gap --json); first_level as --first-level, 'auto' default");
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
        py::arg("columns") = std::vector<std::string>{}, py::arg("source_name") = "",
        "How long to record: per column of a fit/select result's JSON text (source_name: its file; or for model= at "
        "freq=), the record length at which N, K, B or a parameter reach a precision: the document gmwm plan --json "
        "writes");
  m.def("gap_check", &py_gap_check, py::kw_only(), py::arg("cases") = 3, py::arg("n") = std::int64_t{1} << 18,
        py::arg("replicates") = 100, py::arg("strengths") = "2,4,8", py::arg("families") = "", py::arg("null") = true,
        py::arg("seed") = gmwm::kDefaultSeed,
        "The gap diagnosis' self-check on simulated cases with a withheld effect (families 'QN,DR,...', strengths "
        "'2,4,8'): the document gmwm gap-check --json writes");
  gmwm::python::add_other_files_functions(m);
  m.def(
      "figure_units",
      [](const std::string& unit) {
        const gmwm::report::FigureUnits u = gmwm::report::figure_units(unit);
        return std::make_tuple(u.white, u.walk, u.instability, u.quantization, u.ramp);
      },
      py::arg("unit"), "The units of N, K, B, Q and R for data in `unit` (as the documents write them)");
  m.def("model_wv", &py_model_wv, py::arg("model"), py::arg("tau"), py::kw_only(), py::arg("freq") = py::none(),
        "The WV a fully specified model implies at tau (samples), per component: the components' labels and a "
        "components x levels array (the rows sum to the model's WV)");
  m.def("simulate", &py_simulate, py::arg("model"), py::arg("n"), py::kw_only(), py::arg("seed") = gmwm::kDefaultSeed,
        py::arg("signals") = 1, py::arg("freq") = py::none(),
        "Independent series of a fully specified model: shape (n,), or (n, signals) with signal k on stream k, "
        "as gmwm simulate's columns");
}
