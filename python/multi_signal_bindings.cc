// The Python module's functions over several recordings or a result: the joint fit and
// selection over replicates, the export of a fit/select result and the fleet study (each the
// command's study and document, as python/gmwm_module.cc's single-signal functions are).
#include "module_support.h"

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
#include "gmwm/io/fleet_spec.h"
#include "gmwm/io/read_request.h"
#include "gmwm/engine/number_text.h"
#include "gmwm/pipeline/export_study.h"
#include "gmwm/fleet/fleet_cache.h"
#include "gmwm/fleet/fleet_record.h"
#include "gmwm/fleet/fleet_study.h"
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
#include "gmwm/engine/choice.h"

namespace gmwm::python {
namespace {

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
    std::vector<std::string> found;
    std::vector<std::vector<double>> cols = columns_of(recordings[k], &found);
    const std::vector<std::string> labels = names_for(cols.size(), names, found);
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
                         const std::optional<std::string>& estimator, bool spike_screen, const std::string& units_spec,
                         int levels, int max_evaluations, std::optional<double> kf_rate) {
  const ReplicateArrays r = replicate_groups(recordings, freq, names);
  const std::vector<std::string> units = units_of(r.groups, units_spec);
  const double filter = kalman_rate(kf_rate, r.primary);
  gmwm::pipeline::JointFitStudyOptions o;
  o.model = model_spec;
  o.fit.omega = omega_kind(omega);  // as fit --joint --omega: model (the default), diag or full
  o.fit.alpha = alpha;
  o.fit.seed = seed;
  o.fit.max_evaluations = max_evaluations;
  o.wv = wv_levels(alpha, levels, r.primary);
  o.robust = robust_options(robust, eff, estimator, alpha, levels, spike_screen);
  o.test_draws = test_draws;
  o.seed = seed;
  if (const std::string why = o.Validate(); !why.empty()) throw gmwm::InputError(why);
  const gmwm::ProcessContext context{r.primary.freq, r.primary.freq_known};
  gmwm::parse_model(model_spec, context);  // a bad model: InputError, GIL held
  return to_python(run_cancellable([&](const std::function<void(int, int)>& progress) {
    gmwm::pipeline::JointFitStudyOptions oc = o;
    oc.progress = progress;
    const gmwm::pipeline::JointFitStudy study = gmwm::pipeline::study_joint_fit(r.groups, context, oc);
    return gmwm::report::joint_fit_document(r.primary, r.groups, study, units, filter);
  }));
}

// The selection over replicates (gmwm::pipeline::study_joint_select, as `gmwm select
// --joint`): the document gmwm select --joint --json writes (without "run").
std::string py_select_joint(const py::sequence& recordings, const std::string& model_spec, std::optional<double> freq,
                            const std::string& optimism, double alpha, std::uint64_t seed,
                            const std::vector<std::string>& names, bool robust, std::optional<double> eff,
                            const std::optional<std::string>& estimator, bool spike_screen,
                            const std::string& units_spec, int test_draws, int levels, int max_evaluations,
                            std::optional<double> kf_rate) {
  const ReplicateArrays r = replicate_groups(recordings, freq, names);
  const std::vector<std::string> units = units_of(r.groups, units_spec);
  const double filter = kalman_rate(kf_rate, r.primary);
  gmwm::pipeline::JointSelectStudyOptions o;
  o.model = model_spec;
  const std::vector<std::string> joint = gmwm::pipeline::replicate_optimism_names();
  if (std::find(joint.begin(), joint.end(), optimism) == joint.end())
    throw gmwm::InputError("--optimism: " + gmwm::unknown_choice(optimism, joint));
  o.select.select.optimism =
      optimism == "all" ? gmwm::selection::OptimismMethod::kBoth : gmwm::selection::OptimismMethod::kAnalytic;
  o.select.select.seed = seed;
  o.select.select.fit.alpha = alpha;
  o.select.select.fit.seed = seed;
  o.select.select.fit.max_evaluations = max_evaluations;
  o.select.seed = seed;
  o.wv = wv_levels(alpha, levels, r.primary);
  o.robust = robust_options(robust, eff, estimator, alpha, levels, spike_screen);
  o.recommended_test_draws = test_draws;
  if (const std::string why = o.Validate(); !why.empty()) throw gmwm::InputError(why);
  const gmwm::ProcessContext context{r.primary.freq, r.primary.freq_known};
  gmwm::parse_model(model_spec, context);
  return to_python(run_cancellable([&](const std::function<void(int, int)>& progress) {
    gmwm::pipeline::JointSelectStudyOptions oc = o;
    oc.select.select.progress = progress;
    const gmwm::pipeline::JointSelectStudy study = gmwm::pipeline::study_joint_select(r.groups, context, oc);
    return gmwm::report::joint_select_document(r.primary, r.groups, study, units, filter);
  }));
}

// Numbers as Python writes a tuple of them: "(20, 60)", "(5,)".
std::string number_tuple(const std::vector<double>& v) {
  std::string text = "(";
  for (std::size_t i = 0; i < v.size(); ++i) text += (i ? ", " : "") + gmwm::significant(v[i]);
  return text + (v.size() == 1 ? ",)" : ")");
}

// The export (gmwm::pipeline::study_export, as `gmwm export RESULT --format F --output
// OUTPUT`) of a fit/select result's JSON text: (the document gmwm export --json writes
// without "run", the file's text, the sidecar's text or None).
std::tuple<std::string, std::string, std::optional<std::string>> py_export(
    const std::string& result, const std::string& format, const std::string& output, const std::string& aggregate,
    double inflate, std::optional<double> rate, const std::string& rostopic, const std::string& units,
    const std::optional<std::string>& sensor, const std::vector<std::string>& columns,
    const std::optional<std::vector<double>>& consistent_for, const std::string& source_name, bool partial) {
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
  o.format.missing = partial ? gmwm::io::MissingSensor::kLeaveOut : gmwm::io::MissingSensor::kRefuse;
  if (consistent_for) {
    o.consistent_for = gmwm::pipeline::consistency_from(*consistent_for);
    if (!o.consistent_for)
      throw gmwm::InputError("consistent_for " + number_tuple(*consistent_for) +
                             ": expected (rate, horizon[, sigma]): " + gmwm::pipeline::kConsistencyExpected +
                             ", e.g. (20, 60)");
  }
  if (const std::string why = o.Validate(); !why.empty()) throw gmwm::InputError(why);
  gmwm::io::ResultReadOptions ro;
  ro.columns = columns;
  ro.rate = rate;
  if (sensor) {
    const auto kind = gmwm::io::parse_sensor_kind(*sensor);
    if (!kind) throw gmwm::InputError("--sensor: " + gmwm::unknown_choice(*sensor, gmwm::io::sensor_kind_names()));
    ro.sensor = *kind;
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

// A Python runner (gmwm._fleet_dask.runner) as the study's FleetRunner: called with the
// tasks as (index, text) pairs and a done(k, record_text) callable, under the GIL (the study
// itself runs without it).
gmwm::fleet::FleetRunner python_runner(py::object runner) {
  auto shared = std::make_shared<py::object>(std::move(runner));
  return [shared](const std::vector<gmwm::fleet::FleetTask>& tasks,
                  const std::function<void(std::size_t, const std::string&)>& done) {
    py::gil_scoped_acquire gil;
    py::list items;
    for (const gmwm::fleet::FleetTask& t : tasks) items.append(py::make_tuple(t.index, t.text));
    const py::cpp_function hand_back([&done](std::size_t k, const std::string& record) {
      py::gil_scoped_release release;  // the record is parsed and cached without the GIL
      done(k, record);
    });
    (*shared)(items, hand_back);
  };
}

// The manifest's bad rows, all in one gmwm.InputError (a line each, as the CLI prints them).
void refuse_manifest_rows(const std::vector<std::string>& problems) {
  std::string all;
  for (const std::string& p : problems) all += (all.empty() ? "" : "\n") + p;
  // Raised as gmwm.InputError directly: the translator would squeeze the lines into one.
  const py::object input_error = py::module_::import("gmwm._gmwm").attr("InputError");
  PyErr_SetString(input_error.ptr(), all.c_str());
  throw py::error_already_set();
}

// The fleet study (gmwm::fleet::study_fleet, as `gmwm fleet MANIFEST --model SPEC`): the
// document gmwm fleet --json writes (without "run"). `cache`: a folder, "" for the CLI's
// default beside the manifest, None for no cache. `runner`: None (here) or a Python runner.
std::string py_fleet(const std::string& manifest_path, const std::string& model_spec, double alpha, std::uint64_t seed,
                     std::optional<double> memory_mb, std::optional<std::string> cache, py::object runner,
                     const std::string& spec, const std::string& gap_format, const std::string& gap_path,
                     const std::string& gap_imu, int gap_replicates, bool joint, int joint_draws,
                     const py::object& first_level) {
  gmwm::fleet::FleetStudyOptions o;
  o.first_level = first_level_argument(first_level);
  o.model = model_spec;
  o.wv.alpha = alpha;
  o.select.fit.alpha = alpha;
  o.select.fit.seed = seed;
  o.select.seed = seed;
  if (memory_mb) {
    // The one rule for --memory on every face (io::memory_problem).
    if (const std::string why = gmwm::io::memory_problem(*memory_mb, gmwm::significant(*memory_mb)); !why.empty())
      throw gmwm::InputError("--memory: " + why);
    o.memory_budget = *memory_mb * 1e6;
  }
  if (cache) o.cache_dir = cache->empty() ? gmwm::fleet::default_fleet_cache_dir(manifest_path) : *cache;
  if (!spec.empty()) o.spec = gmwm::io::read_fleet_spec(spec);
  o.joint.enabled = joint;
  o.joint.test_draws = joint_draws;
  if (!gap_path.empty()) {
    const std::optional<gmwm::io::SimFormat> format = gmwm::io::parse_sim_format(gap_format);
    if (!format) throw gmwm::InputError("fleet: gap format '" + gap_format + "': expected kalibr, gz-sdf or datasheet");
    o.gap = gmwm::fleet::read_gap_baseline(*format, gap_path, gap_imu, gap_replicates, 100.0);
  }
  if (const std::string why = o.Validate(); !why.empty()) throw gmwm::InputError("fleet: " + why);
  const gmwm::io::FleetManifest manifest = gmwm::io::read_fleet_manifest(manifest_path);
  if (const std::vector<std::string> problems = gmwm::io::fleet_manifest_problems(manifest); !problems.empty())
    refuse_manifest_rows(problems);
  if (!runner.is_none()) {
    // The runner is Python, on this thread: Ctrl-C reaches it as KeyboardInterrupt.
    o.runner = python_runner(std::move(runner));
    gmwm::fleet::FleetStudy study;
    {
      py::gil_scoped_release release;
      study = gmwm::fleet::study_fleet(manifest, o);
    }
    return to_python(gmwm::report::fleet_document(study));
  }
  return to_python(run_cancellable([&](const std::function<void(int, int)>& progress) {
    gmwm::fleet::FleetStudyOptions oc = o;
    oc.progress = progress;  // after each recording
    oc.select.progress = progress;
    return gmwm::report::fleet_document(gmwm::fleet::study_fleet(manifest, oc));
  }));
}

}  // namespace

void add_multi_signal_functions(py::module_& m) {
  m.def("fit_joint", &py_fit_joint, py::arg("replicates"), py::arg("model"), py::kw_only(),
        py::arg("freq") = py::none(), py::arg("omega") = "model", py::arg("alpha") = 0.05,
        py::arg("test_draws") = gmwm::ReplicateTestOptions{}.bootstrap, py::arg("seed") = gmwm::kDefaultSeed,
        py::arg("names") = std::vector<std::string>{}, py::arg("robust") = false, py::arg("eff") = py::none(),
        py::arg("estimator") = py::none(), py::arg("spike_screen") = true, py::arg("units") = "", py::arg("levels") = 0,
        py::arg("max_evaluations") = gmwm::FitOptions{}.max_evaluations, py::arg("kf_rate") = py::none(),
        "Joint (multi-signal) GMWM fit of one model per axis over replicates (recordings of one sensor, each an "
        "array with the same columns): the document gmwm fit --joint --json writes");
  m.def("select_joint", &py_select_joint, py::arg("replicates"), py::arg("model"), py::kw_only(),
        py::arg("freq") = py::none(), py::arg("optimism") = "replicates", py::arg("alpha") = 0.05,
        py::arg("seed") = gmwm::kDefaultSeed, py::arg("names") = std::vector<std::string>{}, py::arg("robust") = false,
        py::arg("eff") = py::none(), py::arg("estimator") = py::none(), py::arg("spike_screen") = true,
        py::arg("units") = "", py::arg("test_draws") = 0, py::arg("levels") = 0,
        py::arg("max_evaluations") = gmwm::FitOptions{}.max_evaluations, py::arg("kf_rate") = py::none(),
        "Selection over replicates (cross-validated WVIC; optimism='all' adds the joint fit's analytic and bootstrap "
        "WVIC): the document gmwm select --joint --json writes");
  m.def("export", &py_export, py::arg("result"), py::kw_only(), py::arg("format"), py::arg("output") = "",
        py::arg("aggregate") = "mean", py::arg("inflate") = 1.0, py::arg("rate") = py::none(),
        py::arg("rostopic") = "/imu0", py::arg("units") = "", py::arg("sensor") = py::none(),
        py::arg("columns") = std::vector<std::string>{}, py::arg("consistent_for") = py::none(),
        py::arg("source_name") = "", py::arg("partial") = false,
        "A fit/select result's noise parameters (its JSON text) in a consumer's format (kalibr, openvins, vins, "
        "orbslam3, basalt, gz-sdf, rotors): (the document gmwm export --json writes, the file's text, the "
        "sidecar's text or None); consistent_for=(rate Hz, horizon s[, update sigma m]) derives the inflation");
  m.def(
      "fleet_task", [](const std::string& task) { return gmwm::fleet::run_fleet_task(task); }, py::arg("task"),
      py::call_guard<py::gil_scoped_release>(),
      "Runs one recording's task text (what a Dask worker runs for gmwm fleet --scheduler): its record's text");
  m.def("fleet", &py_fleet, py::arg("manifest"), py::kw_only(), py::arg("model"), py::arg("alpha") = 0.05,
        py::arg("seed") = gmwm::kDefaultSeed, py::arg("memory") = py::none(), py::arg("cache") = "",
        py::arg("runner") = py::none(), py::arg("spec") = "", py::arg("gap_format") = "kalibr",
        py::arg("gap_path") = "", py::arg("gap_imu") = "",
        py::arg("gap_replicates") = gmwm::fleet::FleetGapBaseline{}.replicates, py::arg("joint") = false,
        py::arg("joint_draws") = gmwm::fleet::FleetStudyOptions::Joint{}.test_draws, py::arg("first_level") = "auto",
        "Every recording of a manifest (CSV or YAML: path, unit, model[, topic, columns, units, rate, group]) "
        "selected over `model` as gmwm select does, one row per unit x axis with N, K, B, the fleet's summary and "
        "the units that stand out: the document gmwm fleet --json writes; `first_level` as the CLI's --first-level");
}

}  // namespace gmwm::python
