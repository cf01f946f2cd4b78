#include "studies.h"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string_view>
#include <utility>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/io/export.h"
#include "gmwm/io/option_wording.h"
#include "gmwm/io/read_request.h"
#include "gmwm/io/sim_config.h"
#include "gmwm/io/units.h"
#include "gmwm/pipeline/export_study.h"
#include "gmwm/pipeline/fit_study.h"
#include "gmwm/pipeline/gap_study.h"
#include "gmwm/pipeline/select_study.h"
#include "gmwm/pipeline/stability_study.h"
#include "gmwm/pipeline/wv_study.h"
#include "gmwm/report/export_output.h"
#include "gmwm/report/html_fragment.h"
#include "gmwm/report/json_output.h"
#include "gmwm/report/report_data.h"
#include "gmwm/report/stability_output.h"
#include "gmwm/report/study_text.h"
#include "gmwm/robust/robust_request.h"
#include "gmwm/robust/robust_wv.h"
#include "gmwm/selection/select.h"
#include "gmwm/engine/choice.h"

namespace gmwm::serve::detail {

namespace {

// The most levels a request may ask for: J levels need 2^J samples (the CLI's --levels).
constexpr std::int64_t kMaxLevels = 62;
// The bootstrap's draws a request may ask for (Omega or optimism): the CLI takes any, but a
// page's request is bounded so that one click cannot occupy the machine for hours.
constexpr std::int64_t kMaxReplicates = 10'000;

// An InputError of the library (a bad model, a unit that does not fit) as the page's 400.
template <class F>
auto as_bad_request(const std::string& where, F&& f) {
  try {
    return f();
  } catch (const InputError& e) {
    throw HttpError(400, io::option_wording(where + ": " + e.what(), io::Face::kWeb));
  }
}

// What every column study takes: the dataset's one column, its unit and filter rate, the
// WV's settings and an optional reference model drawn into the plots.
struct ColumnInput {
  std::shared_ptr<const Dataset> dataset;
  io::SignalSet set;
  std::string unit;
  double filter_rate = 0.0;
  WvOptions wv;
  std::optional<robust::RobustWvOptions> robust;
  std::optional<report::ReportColumn::Reference> reference;
};

std::shared_ptr<const Dataset> find_dataset(const RequestBody& b, Datasets& datasets) {
  const std::string id = b.required_text("dataset", "the id /api/open answered");
  auto d = datasets.find(id);
  if (!d)
    throw HttpError(
        404, b.where() + ": unknown dataset '" + id + "' (datasets are kept while in use: open the recording again)");
  return d;
}

// The request's robust fields (robust, eff, estimator, spike_screen) checked as every face's
// (robust::robust_wv_options), its messages in the page's words.
std::optional<robust::RobustWvOptions> robust_options(const RequestBody& b, const WvOptions& wv) {
  robust::RobustRequest r;
  r.robust = b.flag("robust", false);
  r.eff = b.number("eff");
  if (b.has("estimator")) r.estimator = b.text("estimator");
  r.no_spike_screen = !b.flag("spike_screen", true);
  return as_bad_request(b.where(), [&] { return robust::robust_wv_options(r, wv); });
}

// A simulator's or a datasheet's model of `column` from a file's text (the page's overlay).
struct Baseline {
  Model model;
  Eigen::VectorXd theta;
  std::vector<std::string> conversions;
  std::string source;  ///< the file, or "the pasted <format> file"
  std::string name;    ///< "datasheet: WN+FLICKER", the curve's name
};

Baseline baseline_of(const RequestBody& o, const StudyContext& c, const io::SignalSet& set, const std::string& units) {
  const std::string format_name = o.required_text("format", "datasheet, kalibr, gz-sdf or rotors");
  const auto format = io::parse_sim_format(format_name);
  if (!format) o.fail("format", "found '" + format_name + "', expected datasheet, kalibr, gz-sdf or rotors");
  std::string text, name;
  if (o.has("file")) {
    name = o.text("file");
    const auto path = c.folder.resolve(name, FileKind::kConfig);
    if (!path) throw HttpError(404, o.where() + ": no file '" + name + "' in " + c.folder.name());
    text = path->string();
  } else {
    text = o.required_text("text", "the file's text (or \"file\": a path in the folder)");
    name = o.text("name", "the pasted " + format_name + " file");
  }
  if (!set.freq_known) o.fail("format", "the recording's sampling rate is unknown; a baseline needs it");
  const io::Signal& column = set.signals.front();
  const std::map<io::SensorKind, io::Unit> unit_map = io::parse_units(units);
  const bool unit_check = o.flag("unit_check", true);
  const std::string where = o.where();
  return as_bad_request(where, [&] {
    io::SimConfig config;
    const bool from_file = o.has("file");
    switch (*format) {
      case io::SimFormat::kKalibr:
        config = from_file ? io::read_kalibr_imu_yaml(text, set.freq, unit_map)
                           : io::parse_kalibr_imu_yaml(text, name, set.freq, unit_map);
        break;
      case io::SimFormat::kDatasheet:
        config = from_file ? io::read_datasheet_yaml(text, set.freq, unit_map)
                           : io::parse_datasheet_yaml(text, name, set.freq, unit_map);
        break;
      case io::SimFormat::kGzSensors:
      case io::SimFormat::kRotors:
        config = from_file ? io::read_gazebo_sdf(text, set.freq, unit_map)
                           : io::parse_gazebo_sdf(text, name, set.freq, unit_map);
        break;
    }
    const io::SensorKind kind = io::sensor_kind_of_column(column.name);
    const auto b =
        pipeline::config_baseline(config, kind, column.name, static_cast<std::int64_t>(column.values.size()));
    if (!b)
      throw InputError(name + ": has no " + std::string(io::to_string(kind)) + " figures for column '" + column.name +
                       "'");
    // gap's unit guard: data in deg/s drawn against a baseline read as rad/s would sit
    // (180/pi)^2 above it and look like a gap; the same refusal, naming the units that fit.
    if (unit_check) {
      const std::vector<std::span<const double>> series = {std::span<const double>(column.values)};
      pipeline::check_baseline_units(set.path, column.name, classical_wv(series, WvOptions{}).front(), b->model,
                                     b->theta, std::nullopt, unit_map);
    }
    // Named in the plots by its kind and model (the file is named in the overlay's answer):
    // a file name in the legend would squeeze the plot.
    return Baseline{b->model, b->theta, b->conversions, name, format_name + ": " + b->model.to_string()};
  });
}

// The request's dataset, its one column and the column's declared unit ("units").
ColumnInput column_of(const RequestBody& b, StudyContext& c) {
  ColumnInput in;
  in.dataset = find_dataset(b, c.datasets);
  in.set = column_set(*in.dataset, b.required_text("column", "a column name /api/open listed"), b.where());
  const std::string units = b.text("units");
  as_bad_request(b.where() + ": field 'units'", [&] {
    in.unit = io::unit_of_column(io::parse_units_spec(units), in.set.signals.front().name);
    return 0;
  });
  return in;
}

ColumnInput column_input(const RequestBody& b, StudyContext& c) {
  ColumnInput in = column_of(b, c);
  const std::string units = b.text("units");
  in.filter_rate = in.set.freq_known ? in.set.freq : 0.0;
  if (const auto kf = b.number("kf_rate")) {
    if (!(*kf > 0.0)) b.fail("kf_rate", "expected the filter's rate in Hz, above 0");
    in.filter_rate = *kf;
  }
  if (const auto alpha = b.number("alpha")) {
    if (!(*alpha > 0.0 && *alpha < 1.0)) b.fail("alpha", "expected a number in (0, 1)");
    in.wv.alpha = *alpha;
  }
  if (const auto levels = b.whole("levels", 0, kMaxLevels)) {
    in.wv.levels = static_cast<int>(*levels);
    const auto n = static_cast<std::int64_t>(in.set.signals.front().values.size());
    if (const std::string why = io::levels_problem(in.wv.levels, n, "levels"); !why.empty()) b.fail("levels", why);
  }
  in.robust = robust_options(b, in.wv);
  if (const auto o = b.object("overlay")) {
    Baseline base = baseline_of(*o, c, in.set, units);
    in.reference = report::ReportColumn::Reference{base.name, base.model, base.theta};
  }
  return in;
}

std::vector<std::string> units_of(const ColumnInput& in) { return {in.unit}; }

// A job's result: the CLI's document and text, the report's section and its plots.
Json job_result(Json document, const std::string& text, report::ReportData data, const ColumnInput& in) {
  if (in.reference && !data.columns.empty()) data.columns.front().references.push_back(*in.reference);
  const report::HtmlFragment f = report::render_column_fragment(data, 0);
  return {{"document", std::move(document)}, {"text", text}, {"html", f.html}, {"plots", f.plots}};
}

// A model text of the request, parsed (its values checked) and bound at the data's rate.
ModelSpec model_of(const RequestBody& b, const char* key, const ColumnInput& in) {
  const std::string text = b.required_text(key, "a model such as AR1+WN+RW");
  return as_bad_request(b.where() + ": field '" + key + "'", [&] {
    ModelSpec spec(text);
    spec.bind(ProcessContext{in.set.freq, in.set.freq_known});
    return spec;
  });
}

// What a finished selection keeps for its ranking rows (ranking_row).
struct SelectionKept {
  ColumnInput in;
  pipeline::SelectStudy study;
  std::string model_text;
};

}  // namespace

Jobs::Work wv_work(const RequestBody& body, StudyContext& c) {
  ColumnInput in = column_input(body, c);
  pipeline::WvStudyOptions o;
  o.wv = in.wv;
  o.robust = in.robust;
  if (in.set.freq_known) {
    AllanOptions allan;
    allan.alpha = in.wv.alpha;
    o.allan = allan;
  }
  if (const std::string why = o.Validate(); !why.empty()) throw HttpError(400, body.where() + ": " + why);
  return [in = std::move(in), o](JobContext& job) {
    job.progress(0, 1);
    const pipeline::WvStudy study = pipeline::study_wv(in.set, o);
    job.check();
    const std::vector<std::string> units = units_of(in);
    Json doc = report::wv_document(in.set, study, units);
    const std::string text = (in.set.timing ? in.set.timing->summary() + "\n" : std::string()) +
                             report::wv_text(in.set, study) + report::adev_text(in.set, study, units);
    job.progress(1, 1);
    return job_result(std::move(doc), text, report::wv_report_data(in.set, study, units), in);
  };
}

// "first_level": as --first-level, "auto" or a level given as a string or a whole number.
static int first_level_field(const RequestBody& body) {
  if (!body.has("first_level")) return 1;
  const Json& v = body.json()["first_level"];
  const std::string text = v.is_string() ? v.get<std::string>() : v.is_number_unsigned() ? v.dump() : std::string();
  const std::optional<int> level = text.empty() ? std::nullopt : pipeline::parse_first_level(text);
  if (!level) body.fail("first_level", "found " + v.dump() + ", expected " + pipeline::kFirstLevelExpected);
  return *level;
}

Jobs::Work fit_work(const RequestBody& body, StudyContext& c) {
  ColumnInput in = column_input(body, c);
  pipeline::FitStudyOptions o;
  o.model = model_of(body, "model", in);
  o.wv = in.wv;
  o.robust = in.robust;
  const std::string omega = body.text("omega", "model");
  const auto kind = parse_omega_kind(omega);
  if (!kind) body.fail("omega", unknown_choice(omega, omega_kind_names()));
  o.fit.omega = *kind;
  o.fit.alpha = in.wv.alpha;
  o.fit.seed = c.options.seed;
  if (const auto r = body.whole("replicates", 1, kMaxReplicates)) o.fit.bootstrap_replicates = static_cast<int>(*r);
  o.first_level = first_level_field(body);
  if (const std::string why = o.fit.Validate(); !why.empty()) throw HttpError(400, body.where() + ": " + why);
  const std::string model_text = body.text("model");
  return [in = std::move(in), o, model_text](JobContext& job) mutable {
    o.fit.progress = [&job](int done, int total) { job.progress(done, total); };
    const pipeline::FitStudy study = pipeline::study_fit(in.set, o);
    job.check();
    const std::vector<std::string> units = units_of(in);
    Json doc = report::fit_document(in.set, study, units, in.filter_rate);
    const std::string text = report::fit_text(doc, in.set, study, {units, in.filter_rate, false});
    return job_result(std::move(doc), text, report::fit_report_data(in.set, study, model_text, units, in.filter_rate),
                      in);
  };
}

Jobs::Work select_work(const RequestBody& body, StudyContext& c) {
  ColumnInput in = column_input(body, c);
  pipeline::SelectStudyOptions o;
  // "model" (every sub-model) or "models" ("SPEC1;SPEC2;..."), the rule every face uses.
  as_bad_request(body.where(), [&] {
    pipeline::set_select_models(o, body.text("model"), body.text("models"));
    for (const ModelSpec& spec : o.models) spec.bind(ProcessContext{in.set.freq, in.set.freq_known});
    return 0;
  });
  o.wv = in.wv;
  o.robust = in.robust;
  selection::SelectOptions& s = o.select;
  const auto parse = [&](const char* key, const char* fallback, auto parser, const std::vector<std::string>& names) {
    const std::string text = body.text(key, fallback);
    const auto v = parser(text);
    if (!v) body.fail(key, unknown_choice(text, names));
    return *v;
  };
  s.optimism = parse("optimism", "analytic", selection::parse_optimism_method, selection::optimism_method_names());
  s.omega = parse("omega", "model", selection::parse_omega_source, selection::omega_source_names());
  s.penalty = parse("penalty", "wvic", selection::parse_penalty, selection::penalty_names());
  if (const auto r = body.whole("replicates", 1, kMaxReplicates)) s.bootstrap_replicates = static_cast<int>(*r);
  s.seed = c.options.seed;
  s.fit.alpha = in.wv.alpha;
  s.fit.seed = c.options.seed;
  o.first_level = first_level_field(body);
  if (const std::string why = s.Validate(); !why.empty()) throw HttpError(400, body.where() + ": " + why);
  const std::string model_text = o.listed ? body.text("models") : body.text("model");
  return [in = std::move(in), o, model_text](JobContext& job) mutable {
    o.select.progress = [&job](int done, int total) { job.progress(done, total); };
    const pipeline::SelectStudy study = pipeline::study_select(in.set, o);
    job.check();
    const std::vector<std::string> units = units_of(in);
    Json doc = report::select_document(in.set, study, units, in.filter_rate);
    const std::string text = report::select_text(doc, in.set, study, {units, in.filter_rate, false});
    Json result = job_result(std::move(doc), text,
                             report::select_report_data(in.set, study, model_text, units, in.filter_rate), in);
    job.attach(std::make_shared<const SelectionKept>(SelectionKept{in, study, model_text}));
    return result;
  };
}

Json ranking_row(const std::shared_ptr<const void>& attachment, const std::string& job, const std::string& row) {
  if (!attachment) throw HttpError(404, "job '" + job + "' is not a finished selection");
  const auto& kept = *static_cast<const SelectionKept*>(attachment.get());
  const selection::Selection& sel = kept.study.columns.front().selection;
  std::size_t k = 0;
  const bool digits = !row.empty() && row.size() < 7 && row.find_first_not_of("0123456789") == std::string::npos;
  if (digits) k = std::stoul(row);
  if (k < 1 || k > sel.ranking.size())
    throw HttpError(
        404, "job '" + job + "': no ranking row '" + row + "', expected 1 to " + std::to_string(sel.ranking.size()));
  const selection::RankedModel& r = sel.ranking[k - 1];
  const ColumnInput& in = kept.in;
  const std::vector<std::string> units = units_of(in);
  report::ReportData data = report::select_report_data(in.set, kept.study, kept.model_text, units, in.filter_rate);
  report::ReportColumn& c = data.columns.front();
  c.selection.reset();
  c.fit = report::ranking_row_fit(sel, r);
  c.allan = pipeline::noise_figures_of(in.set, {&*c.fit}, {kept.study.columns.front().wv}, {}, in.wv.alpha).front();
  const Json parameters = report::parameters_json(*c.fit);
  Json out = job_result(Json::object(), "", std::move(data), in);
  out.erase("document");
  out.erase("text");
  out["row"] = k;
  out["rows"] = sel.ranking.size();
  out["rank"] = r.rank;
  out["model"] = r.model;
  out["objective"] = report::json_number(r.objective);
  out["criterion"] = report::json_number(r.criterion);
  out["parameters"] = parameters;
  return out;
}

Json overlay(const RequestBody& body, StudyContext& c) {
  std::shared_ptr<const Dataset> d = find_dataset(body, c.datasets);
  const io::SignalSet set =
      column_set(*d, body.required_text("column", "a column name /api/open listed"), body.where());
  const Baseline b = baseline_of(body, c, set, body.text("units"));
  // The model's WV at the data's dyadic scales (tau_j = 2^j samples, in seconds).
  const auto n = static_cast<std::int64_t>(set.signals.front().values.size());
  std::vector<double> tau_samples;
  for (double t = 2.0; 2.0 * t <= static_cast<double>(n); t *= 2.0) tau_samples.push_back(t);
  const Eigen::VectorXd wv = b.model.wv(b.theta, tau_samples);
  Json tau = Json::array(), values = Json::array();
  for (std::size_t j = 0; j < tau_samples.size(); ++j) {
    tau.push_back(tau_samples[j] / set.freq);
    values.push_back(report::json_number(wv(static_cast<Eigen::Index>(j))));
  }
  return {{"model", b.model.to_string(b.theta)}, {"name", b.name}, {"source", b.source},
          {"conversions", b.conversions},        {"tau", tau},     {"wv", values}};
}

Json export_model(const RequestBody& body) {
  const auto result = body.object("result");
  if (!result) body.fail("result", "missing, expected the document of a fit or select job");
  pipeline::ExportStudyOptions o;
  const std::string format = body.required_text("format", io::export_format_names());
  const auto f = io::parse_export_format(format);
  if (!f) body.fail("format", "found '" + format + "', expected one of " + io::export_format_names());
  o.format.format = *f;
  const std::string aggregate = body.text("aggregate", "mean");
  const auto a = io::parse_aggregation(aggregate);
  if (!a) body.fail("aggregate", "found '" + aggregate + "', expected per-axis, mean or worst");
  o.format.aggregation = *a;
  if (const auto inflate = body.number("inflate")) o.format.inflate = *inflate;
  o.format.rate = body.number("rate");
  o.format.rostopic = body.text("rostopic", o.format.rostopic);
  // As export's --partial: a sensor the result has no column of is refused, never a 0.
  o.format.missing = body.flag("partial", false) ? io::MissingSensor::kLeaveOut : io::MissingSensor::kRefuse;
  io::ResultReadOptions r;
  r.rate = o.format.rate;
  const std::string units = body.text("units");
  const std::string where = body.where();
  return as_bad_request(where, [&] {
    if (const std::string why = o.format.Validate(); !why.empty()) throw InputError(why);
    if (!units.empty()) r.units = io::parse_declared_units(units);
    const io::ResultColumns columns = io::read_result_columns("the page's result", result->json().dump(), r);
    const pipeline::ExportStudy study =
        pipeline::study_export(columns.columns, "gmwm " + columns.command + " result (gmwm serve)", "the result", o);
    const std::string filename = io::default_export_filename(*f);
    Json out = {{"filename", filename},
                {"content", study.result.content},
                {"document", report::export_document(study, filename)},
                {"text", report::export_text(study, filename)},
                {"warnings", study.result.warnings}};
    if (study.result.sidecar) out["sidecar"] = {{"filename", filename + ".txt"}, {"content", *study.result.sidecar}};
    return out;
  });
}

namespace {

// The stability study's options as the library's messages name them (the command's) and the
// request's fields that set them; the library's own field names ("confidence: ...") too: which
// field a refusal of the options names.
constexpr std::pair<std::string_view, const char*> kStabilityFields[] = {{"--kind", "kind"},
                                                                         {"--taus", "taus"},
                                                                         {"--confidence", "confidence"},
                                                                         {"--intervals", "intervals"},
                                                                         {"--noise-alpha", "noise_alpha"},
                                                                         {"confidence", "confidence"},
                                                                         {"noise_alpha", "noise_alpha"}};

// A library message in the page's words: the options as the request's fields, as every face
// words them (io::option_wording: "--taus: 2.5 s is not ..." -> "\"taus\": 2.5 s is not ...").
std::string stability_words(std::string message) { return io::option_wording(std::move(message), io::Face::kWeb); }

// A refusal of the request's options (StabilityStudyOptions::Validate, deviation_of): one line
// naming the field it starts with ("<where>: field 'kind': found 'allan', expected ...").
[[noreturn]] void refuse_stability(const RequestBody& b, const std::string& why) {
  for (const auto& [option, field] : kStabilityFields)
    if (why.starts_with(std::string(option) + ": ")) b.fail(field, why.substr(option.size() + 2));
  throw HttpError(400, stability_words(b.where() + ": " + why));
}

// "taus": "octave", "decade", "all", or averaging times in seconds (a list, or "1,10,100" as
// the command's --taus).
void read_taus(const RequestBody& b, pipeline::StabilityStudyOptions& o) {
  if (!b.has("taus")) return;
  const char* expected = "expected all, octave, decade or averaging times in seconds ([1, 10, 100] or \"1,10,100\")";
  const Json& v = b.json()["taus"];
  if (v.is_string()) {
    const std::string text = v.get<std::string>();
    if (const auto set = stability::tau_set_from_name(text)) {
      o.taus = *set;
      return;
    }
    const std::vector<std::string> entries = io::comma_list(text);
    if (entries.empty()) b.fail("taus", "found '" + text + "', " + expected);
    for (const std::string& entry : entries) {
      char* end = nullptr;
      const double tau = std::strtod(entry.c_str(), &end);
      if (entry.empty() || end != entry.c_str() + entry.size() || !std::isfinite(tau))
        b.fail("taus", "found '" + entry + "', " + expected);
      o.tau_list.push_back(tau);
    }
    return;
  }
  if (!v.is_array() || v.empty()) b.fail("taus", expected);
  for (const Json& t : v) {
    if (!t.is_number() || !std::isfinite(t.get<double>())) b.fail("taus", "found " + t.dump() + ", " + expected);
    o.tau_list.push_back(t.get<double>());
  }
}

// The request's study options ("kind", "taus", "confidence", "intervals", "noise_alpha",
// "hat"), checked by the library's rule (StabilityStudyOptions::Validate) before a job is
// queued.
pipeline::StabilityStudyOptions stability_options(const RequestBody& b) {
  pipeline::StabilityStudyOptions o;
  if (b.has("kind")) {
    o.kinds.clear();
    for (const std::string& name : b.list("kind")) {
      try {
        o.kinds.push_back(stability::deviation_of(name));
      } catch (const InputError& e) {
        refuse_stability(b, e.what());
      }
    }
  }
  read_taus(b, o);
  if (const auto confidence = b.number("confidence")) o.intervals.confidence = *confidence;
  const std::string method = b.text("intervals", "stable32");
  const auto m = stability::interval_method_from_name(method);
  if (!m) b.fail("intervals", "found '" + method + "', expected stable32 or exact");
  o.intervals.method = *m;
  if (b.has("noise_alpha")) {
    const Json& a = b.json()["noise_alpha"];
    const bool whole = a.is_number_integer() && !(a.is_number_unsigned() && a.get<std::uint64_t>() > 1000u);
    if (!whole || a.get<std::int64_t>() < -1000)
      b.fail("noise_alpha", "found " + a.dump() + ", expected an integer from -4 (random-run FM) to 2 (white PM)");
    o.intervals.noise_alpha = static_cast<int>(a.get<std::int64_t>());
  }
  o.three_cornered_hat = b.flag("hat", false);
  if (const std::string why = o.Validate(); !why.empty()) refuse_stability(b, why);
  return o;
}

// What the stability study reads: the dataset's columns the request names and each one's
// declared unit ("" when not).
struct StabilityInput {
  std::shared_ptr<const Dataset> dataset;
  io::SignalSet set;
  std::vector<std::string> units;
};

// "columns" (the hat's A, B, C in their order, as the command's --columns A,B,C) or "column"
// (one), each one's unit of "units"; with "hat", the hat's rule on the columns
// (pipeline::require_hat_columns) before any job, in the page's words.
StabilityInput stability_input(const RequestBody& b, StudyContext& c, const pipeline::StabilityStudyOptions& o) {
  StabilityInput in;
  in.dataset = find_dataset(b, c.datasets);
  if (b.has("columns") && b.has("column")) b.fail("columns", "give \"column\" (one) or \"columns\", not both");
  if (b.has("columns")) {
    const std::vector<std::string> names = b.list("columns");
    if (names.empty()) b.fail("columns", "expected column names /api/open listed");
    in.set = columns_set(*in.dataset, names, "columns", b.where());
  } else {
    in.set = column_set(*in.dataset, b.required_text("column", "a column name /api/open listed"), b.where());
  }
  const std::string units = b.text("units");
  as_bad_request(b.where() + ": field 'units'", [&] {
    const auto spec = io::parse_units_spec(units);
    for (const io::Signal& s : in.set.signals) in.units.push_back(io::unit_of_column(spec, s.name));
    return 0;
  });
  if (o.three_cornered_hat) {
    try {
      pipeline::require_hat_columns(in.set);
    } catch (const InputError& e) {
      throw HttpError(400, stability_words(b.where() + ": " + e.what()));
    }
  }
  return in;
}

// "data": "rate" (the default: the column as /api/open read it) or "phase" (its values a
// phase or time error, read as the rate of their steps, as the command's --data phase).
void read_data(const RequestBody& b, io::SignalSet& set) {
  const std::string data = b.text("data", "rate");
  if (data == "rate") return;
  const std::string expected = "expected rate (a rate or fractional frequency) or phase (a phase or time error)";
  if (data != "phase") b.fail("data", "found '" + data + "', " + expected);
  if (set.data != io::DataKind::kRate)
    b.fail("data", "the recording was opened as " + std::string(io::data_kind_name(set.data)) +
                       " (/api/open's \"data\"); open it as rate to read a column as phase here");
  as_bad_request(b.where(), [&] {
    io::take_phase_as_rate(set, set.path);
    io::find_repeated_samples(set);  // of the rates the study reads, as the command finds them
    return 0;
  });
}

// The study of every kind in one call, its progress told after each averaging factor (the
// page's bar, and a cancel heard there: gmwm::Cancelled from job.progress ends the study);
// the library's refusals of the data in the page's words.
pipeline::StabilityStudy study_with_progress(const io::SignalSet& set, pipeline::StabilityStudyOptions o,
                                             JobContext& job) {
  o.progress = [&job](int done, int total) { job.progress(done, total); };
  try {
    return pipeline::study_stability(set, o);
  } catch (const InputError& e) {
    throw InputError(stability_words(e.what()));
  }
}

// The title of each kind, for the page's choices (docs/stability.md's table).
const char* deviation_title(stability::DeviationKind kind) {
  using K = stability::DeviationKind;
  switch (kind) {
    case K::kAdev:
      return "Allan deviation (non-overlapping)";
    case K::kOadev:
      return "overlapping Allan deviation";
    case K::kMdev:
      return "modified Allan deviation";
    case K::kTdev:
      return "time deviation";
    case K::kHdev:
      return "Hadamard deviation (non-overlapping)";
    case K::kOhdev:
      return "overlapping Hadamard deviation";
    case K::kTotdev:
      return "total deviation";
    case K::kMtotdev:
      return "modified total deviation";
    case K::kTtotdev:
      return "time total deviation";
    case K::kHtotdev:
      return "Hadamard total deviation";
    case K::kTheo1:
      return "Theo1 (at 0.75 m tau0, m even from 10)";
    case K::kMtie:
      return "maximum time interval error";
    case K::kTierms:
      return "rms time interval error";
  }
  return "";
}

}  // namespace

Jobs::Work stability_work(const RequestBody& body, StudyContext& c) {
  const pipeline::StabilityStudyOptions o = stability_options(body);
  StabilityInput in = stability_input(body, c, o);
  read_data(body, in.set);
  return [in = std::move(in), o](JobContext& job) {
    const pipeline::StabilityStudy study = study_with_progress(in.set, o, job);
    job.check();
    Json doc = report::stability_document(in.set, study, o, in.units);
    const std::string text =
        (in.set.timing ? in.set.timing->summary() + "\n" : std::string()) + report::stability_text(study, in.units);
    const report::HtmlFragment f = report::render_stability_fragment(in.set, study, o, in.units);
    return Json{{"document", std::move(doc)}, {"text", text}, {"html", f.html}, {"plots", f.plots}};
  };
}

Json stability_choices() {
  const pipeline::StabilityStudyOptions defaults;
  Json kinds = Json::array();
  for (const stability::DeviationKind k : stability::deviation_kinds()) {
    bool chosen = false;
    for (const stability::DeviationKind d : defaults.kinds) chosen = chosen || d == k;
    kinds.push_back({{"name", std::string(stability::deviation_name(k))},
                     {"title", deviation_title(k)},
                     {"time_units", stability::in_time_units(k)},
                     {"default", chosen}});
  }
  Json taus = Json::array();
  for (const stability::TauSet t : {stability::TauSet::kOctave, stability::TauSet::kDecade, stability::TauSet::kAll})
    taus.push_back(std::string(stability::tau_set_name(t)));
  Json noises = Json::array();
  for (int alpha = 2; alpha >= -4; --alpha)
    noises.push_back({{"alpha", alpha}, {"name", std::string(stability::noise_name(alpha))}});
  return {{"kinds", std::move(kinds)},
          {"taus", std::move(taus)},
          {"default_taus", std::string(stability::tau_set_name(defaults.taus))},
          {"all_taus_max_work", pipeline::kMaxAllTausWork},
          {"confidence", defaults.intervals.confidence},
          {"intervals",
           {std::string(stability::interval_method_name(stability::IntervalMethod::kStable32)),
            std::string(stability::interval_method_name(stability::IntervalMethod::kExact))}},
          {"default_intervals", std::string(stability::interval_method_name(defaults.intervals.method))},
          {"noises", std::move(noises)}};
}

}  // namespace gmwm::serve::detail
