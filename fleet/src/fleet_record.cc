// A fleet's unit of work: the task's and the record's JSON texts (fleet_record.h) and the
// study of one recording (read -> select -> one row per axis).
#include "gmwm/fleet/fleet_record.h"

#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <limits>

#include <nlohmann/json.hpp>

#include "gmwm/engine/error.h"
#include "gmwm/io/side_file.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/io/sim_config.h"
#include "gmwm/io/units.h"
#include "gmwm/pipeline/gap_study.h"
#include "gmwm/pipeline/select_study.h"
#include "gmwm/version.h"

namespace gmwm::fleet {
namespace {

using Json = nlohmann::json;

// --- Numbers: exact, non-finite ones by name --------------------------------------------
// nlohmann writes a double with 17 significant digits, which reads back to the same double.
Json num(double x) {
  if (std::isfinite(x)) return x;
  return std::isnan(x) ? "nan" : x > 0 ? "inf" : "-inf";
}

// What a record or task text held where `field` should be: the one-line reason.
[[noreturn]] void malformed(const std::string& what, const std::string& field, const std::string& expected) {
  throw InputError(what + ": field '" + field + "': expected " + expected);
}

// Reading context: the text's name in messages.
struct Reader {
  std::string what;

  const Json& at(const Json& j, const char* field) const {
    if (!j.is_object() || !j.contains(field)) malformed(what, field, "it to be present");
    return j.at(field);
  }
  double number(const Json& j, const char* field) const {
    const Json& v = at(j, field);
    if (v.is_number()) return v.get<double>();
    if (v.is_string()) {
      const std::string s = v.get<std::string>();
      if (s == "nan") return std::numeric_limits<double>::quiet_NaN();
      if (s == "inf") return std::numeric_limits<double>::infinity();
      if (s == "-inf") return -std::numeric_limits<double>::infinity();
    }
    malformed(what, field, "a number, \"nan\", \"inf\" or \"-inf\"");
  }
  std::int64_t integer(const Json& j, const char* field) const {
    const Json& v = at(j, field);
    if (!v.is_number_integer()) malformed(what, field, "an integer");
    return v.get<std::int64_t>();
  }
  std::string text(const Json& j, const char* field) const {
    const Json& v = at(j, field);
    if (!v.is_string()) malformed(what, field, "a string");
    return v.get<std::string>();
  }
  bool flag(const Json& j, const char* field) const {
    const Json& v = at(j, field);
    if (!v.is_boolean()) malformed(what, field, "true or false");
    return v.get<bool>();
  }
  std::vector<double> numbers(const Json& j, const char* field) const {
    const Json& v = at(j, field);
    if (!v.is_array()) malformed(what, field, "an array of numbers");
    std::vector<double> out;
    out.reserve(v.size());
    for (const Json& x : v) out.push_back(number(Json{{"x", x}}, "x"));
    return out;
  }
  std::vector<std::int64_t> integers(const Json& j, const char* field) const {
    const Json& v = at(j, field);
    if (!v.is_array()) malformed(what, field, "an array of integers");
    std::vector<std::int64_t> out;
    out.reserve(v.size());
    for (const Json& x : v) {
      if (!x.is_number_integer()) malformed(what, field, "an array of integers");
      out.push_back(x.get<std::int64_t>());
    }
    return out;
  }
  std::vector<std::string> texts(const Json& j, const char* field) const {
    const Json& v = at(j, field);
    if (!v.is_array()) malformed(what, field, "an array of strings");
    std::vector<std::string> out;
    for (const Json& x : v) {
      if (!x.is_string()) malformed(what, field, "an array of strings");
      out.push_back(x.get<std::string>());
    }
    return out;
  }
  template <class E>
  E named(const Json& j, const char* field, std::optional<E> (*parse)(const std::string&)) const {
    const std::string s = text(j, field);
    const std::optional<E> e = parse(s);
    if (!e) malformed(what, field, "a known name, not '" + printable_line(s) + "'");
    return *e;
  }
};

Json numbers_json(const std::vector<double>& v) {
  Json a = Json::array();
  for (double x : v) a.push_back(num(x));
  return a;
}

// --- Options ------------------------------------------------------------------------------
Json fit_json(const FitOptions& f) {
  return {{"omega", to_string(f.omega)},
          {"alpha", num(f.alpha)},
          {"multistarts", f.multistarts},
          {"max_evaluations", f.max_evaluations},
          {"relative_tolerance", num(f.relative_tolerance)},
          {"bootstrap_replicates", f.bootstrap_replicates},
          {"seed", f.seed},
          {"inference", f.inference},
          {"nested_starts", f.nested_starts},
          {"nested_depth", f.nested_depth}};
}

FitOptions read_fit(const Reader& r, const Json& j) {
  FitOptions f;
  f.omega = r.named<OmegaKind>(j, "omega", &parse_omega_kind);
  f.alpha = r.number(j, "alpha");
  f.multistarts = static_cast<int>(r.integer(j, "multistarts"));
  f.max_evaluations = static_cast<int>(r.integer(j, "max_evaluations"));
  f.relative_tolerance = r.number(j, "relative_tolerance");
  f.bootstrap_replicates = static_cast<int>(r.integer(j, "bootstrap_replicates"));
  const Json& seed = r.at(j, "seed");
  if (!seed.is_number_unsigned() && !seed.is_number_integer()) malformed(r.what, "seed", "an unsigned integer");
  f.seed = seed.get<std::uint64_t>();
  f.inference = r.flag(j, "inference");
  f.nested_starts = r.flag(j, "nested_starts");
  f.nested_depth = static_cast<int>(r.integer(j, "nested_depth"));
  return f;
}

// Everything of the options that decides the result, with the library's version.
Json gap_json(const std::optional<FleetGapBaseline>& g) {
  if (!g) return nullptr;
  return {{"format", to_string(g->format)},
          {"name", g->name},
          {"text", g->text},
          {"imu", g->imu},
          {"replicates", g->replicates}};
}

std::optional<FleetGapBaseline> read_gap(const Reader& r, const Json& j) {
  if (j.is_null()) return std::nullopt;
  FleetGapBaseline g;
  g.format = r.named<io::SimFormat>(j, "format", &io::parse_sim_format);
  g.name = r.text(j, "name");
  g.text = r.text(j, "text");
  g.imu = r.text(j, "imu");
  g.replicates = static_cast<int>(r.integer(j, "replicates"));
  return g;
}

Json result_options_json(const FleetStudyOptions& o) {
  const selection::SelectOptions& s = o.select;
  return {{"library", library_version()},
          {"gap", gap_json(o.gap)},
          {"model", o.model.text()},
          {"wv", {{"levels", o.wv.levels}, {"alpha", num(o.wv.alpha)}}},
          {"first_level", o.first_level},
          {"select",
           {{"penalty", to_string(s.penalty)},
            {"omega", to_string(s.omega)},
            {"optimism", to_string(s.optimism)},
            {"bootstrap_replicates", s.bootstrap_replicates},
            {"seed", s.seed},
            {"fit", fit_json(s.fit)}}}};
}

FleetStudyOptions read_options(const Reader& r, const Json& j) {
  FleetStudyOptions o;
  o.model = ModelSpec(r.text(j, "model"));
  const Json& wv = r.at(j, "wv");
  o.wv.levels = static_cast<int>(r.integer(wv, "levels"));
  o.wv.alpha = r.number(wv, "alpha");
  o.first_level = static_cast<int>(r.integer(j, "first_level"));
  const Json& s = r.at(j, "select");
  o.select.penalty = r.named<selection::Penalty>(s, "penalty", &selection::parse_penalty);
  o.select.omega = r.named<selection::OmegaSource>(s, "omega", &selection::parse_omega_source);
  o.select.optimism = r.named<selection::OptimismMethod>(s, "optimism", &selection::parse_optimism_method);
  o.select.bootstrap_replicates = static_cast<int>(r.integer(s, "bootstrap_replicates"));
  const Json& seed = r.at(s, "seed");
  if (!seed.is_number_unsigned() && !seed.is_number_integer()) malformed(r.what, "seed", "an unsigned integer");
  o.select.seed = seed.get<std::uint64_t>();
  o.select.fit = read_fit(r, r.at(s, "fit"));
  o.gap = read_gap(r, r.at(j, "gap"));
  return o;
}

Json reading_json(const io::FleetRecording& rec) {
  return {{"topic", rec.topic},
          {"columns", rec.columns},
          {"units", rec.units},
          {"rate", rec.rate ? num(*rec.rate) : Json(nullptr)}};
}

io::FleetRecording read_reading(const Reader& r, const Json& j) {
  io::FleetRecording rec;
  rec.topic = r.text(j, "topic");
  rec.columns = r.text(j, "columns");
  rec.units = r.text(j, "units");
  if (!r.at(j, "rate").is_null()) rec.rate = r.number(j, "rate");
  return rec;
}

// --- Results ------------------------------------------------------------------------------
Json readoff_json(const Readoff& f) {
  Json sources = Json::array();
  for (const auto& [name, share] : f.sources) sources.push_back({{"component", name}, {"share", num(share)}});
  return {{"value", num(f.value)},         {"low", num(f.low)}, {"high", num(f.high)},
          {"status", to_string(f.status)}, {"tau", num(f.tau)}, {"region_from", num(f.region_from)},
          {"region_to", num(f.region_to)}, {"how", f.how},      {"sources", std::move(sources)}};
}

Readoff read_readoff(const Reader& r, const Json& j) {
  Readoff f;
  f.value = r.number(j, "value");
  f.low = r.number(j, "low");
  f.high = r.number(j, "high");
  f.status = r.named<ReadoffStatus>(j, "status", &parse_readoff_status);
  f.tau = r.number(j, "tau");
  f.region_from = r.number(j, "region_from");
  f.region_to = r.number(j, "region_to");
  f.how = r.text(j, "how");
  const Json& sources = r.at(j, "sources");
  if (!sources.is_array()) malformed(r.what, "sources", "an array");
  for (const Json& s : sources) f.sources.emplace_back(r.text(s, "component"), r.number(s, "share"));
  return f;
}

Json chosen_json(const ChosenFigure& c) {
  return {{"figure", readoff_json(c.figure)},
          {"source", to_string(c.source)},
          {"note", c.note},
          {"model", readoff_json(c.model)},
          {"data", readoff_json(c.data)}};
}

ChosenFigure read_chosen(const Reader& r, const Json& j) {
  ChosenFigure c;
  c.figure = read_readoff(r, r.at(j, "figure"));
  c.source = r.named<FigureSource>(j, "source", &parse_figure_source);
  c.note = r.text(j, "note");
  c.model = read_readoff(r, r.at(j, "model"));
  c.data = read_readoff(r, r.at(j, "data"));
  return c;
}

Json wv_json(const WaveletVariance& wv) {
  Json replaced = Json::array();
  for (const auto& [first, last] : wv.replaced) replaced.push_back({first, last});
  return {{"tau", numbers_json(wv.tau)},
          {"wv", numbers_json(wv.wv)},
          {"ci_low", numbers_json(wv.ci_low)},
          {"ci_high", numbers_json(wv.ci_high)},
          {"variance", numbers_json(wv.variance)},
          {"eta", numbers_json(wv.eta)},
          {"coefficients", wv.coefficients},
          {"partial", wv.partial},
          {"alpha", num(wv.alpha)},
          {"n", wv.n},
          {"estimator", wv.estimator},
          {"efficiency", wv.efficiency ? num(*wv.efficiency) : Json(nullptr)},
          {"notes", wv.notes},
          {"small_sample", wv.small_sample},
          {"replaced", std::move(replaced)},
          {"screening", wv.screening}};
}

WaveletVariance read_wv(const Reader& r, const Json& j) {
  WaveletVariance wv;
  wv.tau = r.numbers(j, "tau");
  wv.wv = r.numbers(j, "wv");
  wv.ci_low = r.numbers(j, "ci_low");
  wv.ci_high = r.numbers(j, "ci_high");
  wv.variance = r.numbers(j, "variance");
  wv.eta = r.numbers(j, "eta");
  wv.coefficients = r.integers(j, "coefficients");
  wv.partial = r.integers(j, "partial");
  wv.alpha = r.number(j, "alpha");
  wv.n = r.integer(j, "n");
  wv.estimator = r.text(j, "estimator");
  if (!r.at(j, "efficiency").is_null()) wv.efficiency = r.number(j, "efficiency");
  wv.notes = r.texts(j, "notes");
  wv.small_sample = r.text(j, "small_sample");
  for (const Json& p : r.at(j, "replaced")) {
    if (!p.is_array() || p.size() != 2 || !p[0].is_number_integer() || !p[1].is_number_integer())
      malformed(r.what, "replaced", "pairs of integers");
    wv.replaced.emplace_back(p[0].get<std::int64_t>(), p[1].get<std::int64_t>());
  }
  wv.screening = r.text(j, "screening");
  const std::size_t J = wv.wv.size();
  for (const auto* v : {&wv.tau, &wv.ci_low, &wv.ci_high, &wv.variance, &wv.eta})
    if (v->size() != J) malformed(r.what, "wv", "arrays of one length per level");
  if (wv.coefficients.size() != J) malformed(r.what, "wv", "arrays of one length per level");
  if (!wv.partial.empty() && wv.partial.size() != J)
    malformed(r.what, "wv", "partial empty (a record without missing samples) or one count per level");
  return wv;
}

Json adev_json(const AllanDeviation& a) {
  return {{"m", a.m},
          {"tau", numbers_json(a.tau)},
          {"adev", numbers_json(a.adev)},
          {"ci_low", numbers_json(a.ci_low)},
          {"ci_high", numbers_json(a.ci_high)},
          {"edf", numbers_json(a.edf)},
          {"complete", a.complete},
          {"partial", a.partial},
          {"freq", num(a.freq)},
          {"n", a.n},
          {"alpha", num(a.alpha)}};
}

AllanDeviation read_adev(const Reader& r, const Json& j) {
  AllanDeviation a;
  a.m = r.integers(j, "m");
  a.tau = r.numbers(j, "tau");
  a.adev = r.numbers(j, "adev");
  a.ci_low = r.numbers(j, "ci_low");
  a.ci_high = r.numbers(j, "ci_high");
  a.edf = r.numbers(j, "edf");
  a.complete = r.integers(j, "complete");
  a.partial = r.integers(j, "partial");
  a.freq = r.number(j, "freq");
  a.n = r.integer(j, "n");
  a.alpha = r.number(j, "alpha");
  for (const auto* v : {&a.tau, &a.adev, &a.ci_low, &a.ci_high, &a.edf})
    if (v->size() != a.m.size()) malformed(r.what, "adev", "arrays of one length per averaging factor");
  for (const auto* v : {&a.complete, &a.partial})
    if (!v->empty() && v->size() != a.m.size())
      malformed(r.what, "adev", "complete and partial empty (a record without missing samples) or one per factor");
  return a;
}

// The record's missing runs ([start, length] pairs on the grid), checked against its first
// axis's observed samples (missing_runs_problem): a crafted record is refused naming the
// field, never read into a grid its WV does not describe.
std::vector<MissingRun> read_missing(const Reader& r, const Json& j, const Json& axes) {
  if (!j.is_array()) malformed(r.what, "missing", "an array of [start, length] pairs");
  std::vector<MissingRun> out;
  for (const Json& p : j) {
    if (!p.is_array() || p.size() != 2 || !p[0].is_number_integer() || !p[1].is_number_integer())
      malformed(r.what, "missing", "an array of [start, length] pairs");
    out.push_back({p[0].get<std::int64_t>(), p[1].get<std::int64_t>()});
  }
  if (out.empty()) return out;
  const std::int64_t observed = axes.empty() || !axes.front().is_object() ? 0 : r.integer(axes.front(), "n");
  if (const std::string why = missing_runs_problem(observed, out); !why.empty())
    malformed(r.what, "missing", "runs on the grid of the axes' samples (" + why + ")");
  return out;
}

Json axis_json(const FleetRow& row, const FleetCurves& c) {
  Json figures = nullptr;
  if (row.figures_known) {
    figures = Json::object();
    for (int k = 0; k < kFigureCount; ++k)
      figures[std::string(1, kFigureNames[k].symbol)] = chosen_json(row.figures[k]);  // "N", "K", "B", "Q", "R"
  }
  return {
      {"axis", row.axis},
      {"data_unit", row.data_unit},
      {"status", row.status},
      {"chosen", row.chosen},
      {"chosen_structure", row.chosen_structure},
      {"gof_p", num(row.gof_p)},
      {"n", row.n},
      {"first_level", row.first_level},
      {"figures", std::move(figures)},
      {"gap", row.gap_verdict.empty()
                  ? Json(nullptr)
                  : Json{{"verdict", row.gap_verdict}, {"headline", row.gap_headline}, {"p_value", num(row.gap_p)}}},
      {"wv", wv_json(c.wv)},
      {"adev", adev_json(c.adev)},
      {"model_adev", numbers_json(c.model)}};
}

void read_axis(const Reader& r, const Json& j, FleetRow& row, FleetCurves& c) {
  row.axis = r.text(j, "axis");
  row.data_unit = r.text(j, "data_unit");
  row.status = r.text(j, "status");
  row.chosen = r.text(j, "chosen");
  row.chosen_structure = r.text(j, "chosen_structure");
  row.gof_p = r.number(j, "gof_p");
  row.n = r.integer(j, "n");
  row.first_level = static_cast<int>(r.integer(j, "first_level"));
  const Json& f = r.at(j, "figures");
  if (!f.is_null()) {
    for (int k = 0; k < kFigureCount; ++k)
      row.figures[k] = read_chosen(r, r.at(f, std::string(1, kFigureNames[k].symbol).c_str()));
    row.figures_known = true;
  }
  if (const Json& gap = r.at(j, "gap"); !gap.is_null()) {
    row.gap_verdict = r.text(gap, "verdict");
    row.gap_headline = r.text(gap, "headline");
    row.gap_p = r.number(gap, "p_value");
  }
  c.wv = read_wv(r, r.at(j, "wv"));
  c.adev = read_adev(r, r.at(j, "adev"));
  c.model = r.numbers(j, "model_adev");
}

// --- The study of one recording ------------------------------------------------------------
double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// Stage 1: the recording's signals, as the manifest row says to read them.
io::SignalSet read_recording(const io::FleetRecording& r, const FleetStudyOptions& o) {
  io::ReadOptions read;
  if (!r.columns.empty()) read.columns = io::manifest_columns(r.columns);
  read.freq = r.rate;
  read.topic = r.topic;
  read.memory_budget = o.memory_budget;
  io::SignalSet set = io::read_signals(r.path, read);
  if (!set.freq_known) throw InputError(r.path + ": found no timestamp column, expected one or the row's rate");
  return set;
}

// Stage 2: each axis's row and curves from the selection study.
void add_axes(const io::FleetRecording& r, const io::SignalSet& set, pipeline::SelectStudy& study, FleetRecord& out) {
  const io::UnitsSpec units = io::parse_units_spec(r.units);
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    pipeline::SelectColumnStudy& c = study.columns[k];
    FleetRow row;
    row.axis = c.name;
    row.data_unit = r.units.empty() ? set.signals[k].unit : io::unit_of_column(units, c.name);
    row.n = static_cast<std::int64_t>(set.signals[k].values.size());
    row.freq = set.freq;
    row.first_level = c.first_level;
    const FitResult& b = c.selection.best_fit;
    if (b.status == FitStatus::kFailed || b.theta.size() != b.model.num_parameters() || !b.theta.allFinite()) {
      row.status =
          "the chosen model's fit failed" + (b.message.empty() ? std::string() : ": " + printable_line(b.message));
    } else {
      row.chosen = b.model.to_string(b.theta);
      row.chosen_structure = b.model.to_string();
      row.gof_p = b.gof.p_value;
    }
    FleetCurves curves;
    curves.wv = std::move(c.wv);
    curves.wv.covariance.reset();  // the estimators leave it unset; a record carries none
    curves.missing = set.missing;
    if (c.figures) {
      row.figures = c.figures->chosen;
      row.figures_known = true;
      curves.adev = std::move(c.figures->adev);
      curves.model = std::move(c.figures->model_adev);
    }
    out.axes.push_back(std::move(row));
    out.curves.push_back(std::move(curves));
  }
}

std::string task_what() { return "fleet task"; }

// A task's or record's JSON of this version; InputError naming r.what otherwise.
Json parse_versioned(const std::string& text, const Reader& r) {
  Json j;
  try {
    j = Json::parse(text);
  } catch (const Json::exception& e) {
    throw InputError(r.what + ": not JSON (" + e.what() + ")");
  }
  if (r.integer(j, "version") != kFleetRecordVersion) malformed(r.what, "version", std::to_string(kFleetRecordVersion));
  return j;
}

// The baseline's configuration at the recording's rate and units.
io::SimConfig gap_config(const FleetGapBaseline& g, double freq, const std::map<io::SensorKind, io::Unit>& units) {
  switch (g.format) {
    case io::SimFormat::kDatasheet:
      return io::parse_datasheet_yaml(g.text, g.name, freq, units);
    case io::SimFormat::kGzSensors:
    case io::SimFormat::kRotors:
      return io::parse_gazebo_sdf(g.text, g.name, freq, units);
    case io::SimFormat::kKalibr:
      break;
  }
  return io::parse_kalibr_imu_yaml(g.text, g.name, freq, units, g.imu);
}

// The diagnosis' verdict in a word, as FleetRow::gap_verdict says.
std::string gap_verdict(const gap::GapResult& r) {
  if (!r.detected) return "none";
  return r.closed ? "closed" : "remains";
}

// Stage 3 (with a baseline): each axis's gap diagnosis, as `gmwm gap` gives it; a recording
// the diagnosis refuses (a unit mix-up, no figure for its sensor) keeps its selection, every
// axis saying why it was not diagnosed.
void add_gap(const io::FleetRecording& r, io::SignalSet& set, const FleetStudyOptions& o, FleetRecord& out) {
  try {
    pipeline::GapStudyOptions go;
    go.units = io::parse_units(r.units);
    go.units_declared = !r.units.empty();
    go.baseline = pipeline::ConfigBaseline{gap_config(*o.gap, set.freq, go.units), o.gap->name};
    go.wv = o.wv;
    go.first_level = o.first_level;
    go.gap.replicates = o.gap->replicates;
    go.gap.seed = o.select.seed;
    const pipeline::GapStudy g = pipeline::study_gap(set, go);
    for (FleetRow& row : out.axes)
      for (const pipeline::GapColumnStudy& c : g.columns)
        if (c.name == row.axis) {
          row.gap_verdict = gap_verdict(c.result);
          row.gap_headline = printable_line(c.result.headline);
          row.gap_p = c.result.p_value;
        }
  } catch (const Cancelled&) {
    throw;
  } catch (const std::exception& e) {
    for (FleetRow& row : out.axes) {
      row.gap_verdict = "not diagnosed";
      row.gap_headline = printable_line(e.what());
    }
  }
}

}  // namespace

FleetGapBaseline read_gap_baseline(io::SimFormat format, const std::string& path, const std::string& imu,
                                   int replicates, double nominal_freq) {
  FleetGapBaseline g;
  g.format = format == io::SimFormat::kRotors ? io::SimFormat::kGzSensors : format;
  g.name = path;
  g.imu = imu;
  g.replicates = replicates;
  g.text = io::read_side_file(path, "a gap baseline (" + std::string(io::to_string(g.format)) + ")");
  gap_config(g, nominal_freq, {});  // refuses a file that is not one, naming its line
  return g;
}

FleetRecord study_fleet_recording(const io::FleetRecording& recording, const FleetStudyOptions& options) {
  const auto t = std::chrono::steady_clock::now();
  FleetRecord out;
  try {
    io::SignalSet set = read_recording(recording, options);
    out.freq = set.freq;
    pipeline::SelectStudyOptions so;
    so.models = {options.model};
    so.select = options.select;
    so.wv = options.wv;
    so.first_level = options.first_level;
    pipeline::SelectStudy s = pipeline::study_select(set, so);
    add_axes(recording, set, s, out);
    if (options.gap) add_gap(recording, set, options, out);
  } catch (const Cancelled&) {
    throw;
  } catch (const std::exception& e) {
    const double freq = out.freq;  // known when the recording was read and what followed failed
    out = FleetRecord{};
    out.freq = freq;
    out.status = printable_line(e.what());
  }
  out.seconds = seconds_since(t);
  for (FleetRow& row : out.axes) row.seconds = out.seconds;
  return out;
}

std::string fleet_task_text(const io::FleetRecording& recording, const FleetStudyOptions& options) {
  if (const std::string why = options.Validate(); !why.empty()) throw InputError("fleet: " + why);
  // An absolute path: a worker elsewhere runs in another folder (it must see the same files).
  std::error_code ec;
  const std::filesystem::path absolute = std::filesystem::absolute(recording.path, ec);
  Json task = {{"version", kFleetRecordVersion},
               {"path", ec ? recording.path : absolute.string()},
               {"reading", reading_json(recording)},
               {"options", result_options_json(options)},
               {"memory_budget", num(options.memory_budget)}};
  return task.dump();
}

std::string fleet_result_key_text(const io::FleetRecording& recording, const FleetStudyOptions& options) {
  Json key = {{"version", kFleetRecordVersion},
              {"reading", reading_json(recording)},
              {"options", result_options_json(options)}};
  return key.dump();
}

std::string run_fleet_task(const std::string& task_text, const std::function<void(int, int)>& select_progress) {
  const Reader r{task_what()};
  const Json task = parse_versioned(task_text, r);
  io::FleetRecording rec = read_reading(r, r.at(task, "reading"));
  rec.path = r.text(task, "path");
  FleetStudyOptions o = read_options(r, r.at(task, "options"));
  o.memory_budget = r.number(task, "memory_budget");
  o.select.progress = select_progress;
  if (const std::string why = o.Validate(); !why.empty()) throw InputError(task_what() + ": " + why);
  return fleet_record_text(study_fleet_recording(rec, o));
}

std::string fleet_record_text(const FleetRecord& record) {
  Json axes = Json::array();
  for (std::size_t k = 0; k < record.axes.size(); ++k) axes.push_back(axis_json(record.axes[k], record.curves[k]));
  Json missing = Json::array();  // the recording's, shared by its axes
  if (!record.curves.empty())
    for (const MissingRun& m : record.curves.front().missing) missing.push_back({m.start, m.length});
  Json j = {{"version", kFleetRecordVersion}, {"status", record.status},       {"freq", num(record.freq)},
            {"seconds", num(record.seconds)}, {"missing", std::move(missing)}, {"axes", std::move(axes)}};
  return j.dump();
}

std::string failed_record_text(const std::string& why) {
  FleetRecord r;
  r.status = printable_line(why.empty() ? std::string("the task failed without a reason") : why);
  return fleet_record_text(r);
}

FleetRecord parse_fleet_record(const std::string& text, const std::string& source) {
  const Reader r{source};
  const Json j = parse_versioned(text, r);
  FleetRecord out;
  out.status = r.text(j, "status");
  out.freq = r.number(j, "freq");
  out.seconds = r.number(j, "seconds");
  const Json& axes = r.at(j, "axes");
  if (!axes.is_array()) malformed(source, "axes", "an array");
  const std::vector<MissingRun> missing = read_missing(r, r.at(j, "missing"), axes);
  for (const Json& a : axes) {
    FleetRow row;
    FleetCurves c;
    read_axis(r, a, row, c);
    c.missing = missing;
    row.freq = out.freq;
    row.seconds = out.seconds;
    out.axes.push_back(std::move(row));
    out.curves.push_back(std::move(c));
  }
  return out;
}

}  // namespace gmwm::fleet
