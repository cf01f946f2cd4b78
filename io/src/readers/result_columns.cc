// The fitted models of a `gmwm fit --json` / `gmwm select --json` document, as the columns
// an export takes (read_result_columns, export.h). The field names are the docs/cli.md contract:
// per column "name", "n", "freq" and "model" (fit) or "best_model" (select), a canonical
// model string with its values usable as SPEC_WITH_VALUES.

#include <nlohmann/json.hpp>

#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/io/export.h"
#include "gmwm/io/side_file.h"

namespace gmwm::io {
namespace {

using nlohmann::json;

const char* kExpected = "expected the --json result of gmwm fit or gmwm select";

// "path:line:column: " of a byte offset (1-based, as nlohmann reports it).
std::string place(const std::string& path, const std::string& text, std::size_t byte) {
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i + 1 < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return path + ":" + std::to_string(line) + ":" + std::to_string(column) + ": ";
}

std::string names_of(const json& columns) {
  std::string out;
  for (const auto& c : columns)
    if (c.is_object() && c.contains("name") && c["name"].is_string())
      out += (out.empty() ? "" : ", ") + c["name"].get<std::string>();
  return out;
}

// The noise figures a fit/select result chose (json_noise.cc), when it has them all.
std::optional<ExportFigures> figures_of(const json& c) {
  if (!c.contains("noise_figures") || !c["noise_figures"].is_object()) return std::nullopt;
  const json& nf = c["noise_figures"];
  ExportFigures out;
  for (auto [key, f] :
       {std::pair{"white", &out.white}, std::pair{"walk", &out.walk}, std::pair{"instability", &out.instability}}) {
    if (!nf.contains(key) || !nf[key].is_object()) return std::nullopt;
    const json& x = nf[key];
    if (!x.contains("value") || !x["value"].is_number() || !(x["value"].get<double>() > 0.0)) return std::nullopt;
    f->value = x["value"].get<double>();
    f->source = x.contains("source") && x["source"].is_string() ? x["source"].get<std::string>() : "model";
    f->note = x.contains("note") && x["note"].is_string() ? x["note"].get<std::string>() : std::string();
  }
  return out;
}

// The unit the column's numbers are in: the result's own "unit" (what its fit was told with
// --units), or the export's --units for a result that does not say. A result that says
// nothing, with no --units, is refused rather than taken as SI (a deg/s fit exported as
// rad/s is 57x off); so is an export --units that contradicts the result's own.
Unit result_unit(const json& c, SensorKind kind, const ResultReadOptions& o, const std::string& at) {
  std::optional<Unit> declared;
  if (c.contains("unit") && !c["unit"].is_null()) {
    if (!c["unit"].is_string())
      throw InputError(at + "found \"unit\": " + std::string(c["unit"].type_name()) +
                       ", expected a unit name such as \"deg/s\"");
    try {
      declared = parse_unit(c["unit"].get<std::string>(), kind);
    } catch (const InputError& err) {
      throw InputError(at + "\"unit\": " + err.what());
    }
  }
  const auto given = o.units ? o.units->find(kind) : std::map<SensorKind, Unit>::const_iterator{};
  const bool has_given = o.units && given != o.units->end();
  if (declared && has_given && given->second.name != declared->name)
    throw InputError(at + "--units says " + to_string(kind) + "=" + given->second.name +
                     ", but the result was fitted on " + declared->name +
                     " data (its \"unit\"); leave --units out or give " + to_string(kind) + "=" + declared->name);
  if (declared) return *declared;
  if (has_given) return given->second;
  throw InputError(at + "the result does not say the data's unit (it was fitted without --units); give --units " +
                   to_string(kind) + "=UNIT, the unit of the data it was fitted on (" + to_string(kind) +
                   (kind == SensorKind::kGyro ? ": rad/s, deg/s or deg/h)" : ": m/s^2, g or mg)"));
}

}  // namespace

ResultColumns read_result_columns(const std::string& path, const ResultReadOptions& o) {
  return read_result_columns(path, read_side_file(path, "the --json result of gmwm fit or gmwm select"), o);
}

ResultColumns read_result_columns(const std::string& path, const std::string& text, const ResultReadOptions& o) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::parse_error& e) {
    throw InputError(place(path, text, e.byte) + "invalid JSON, " + kExpected);
  } catch (const json::exception& e) {  // e.g. a number beyond the range of a double (found by fuzzing)
    throw InputError(path + ": invalid JSON (" + e.what() + "), " + kExpected);
  }
  if (!doc.is_object() || !doc.contains("tool") || doc["tool"] != "gmwm" || !doc.contains("command") ||
      !doc["command"].is_string())
    throw InputError(path + ": not a gmwm JSON document (no \"tool\": \"gmwm\" with a \"command\"), " + kExpected);
  ResultColumns r;
  r.command = doc["command"].get<std::string>();
  if (r.command != "fit" && r.command != "select")
    throw InputError(path + ": a gmwm " + r.command + " document holds no fitted model, " + kExpected);
  if (doc.contains("input") && doc["input"].is_string()) r.input = doc["input"].get<std::string>();
  if (!doc.contains("columns") || !doc["columns"].is_array() || doc["columns"].empty())
    throw InputError(path + ": no \"columns\" in the document, " + kExpected);
  const json& all = doc["columns"];

  // The columns to export, in the requested order.
  std::vector<const json*> picked;
  if (o.columns.empty()) {
    for (const auto& c : all) picked.push_back(&c);
  } else {
    for (const auto& name : o.columns) {
      const json* found = nullptr;
      for (const auto& c : all)
        if (c.is_object() && c.contains("name") && c["name"] == name) found = &c;
      if (!found)
        throw InputError(path + ": --columns: no column '" + name + "' in the result (it has " + names_of(all) + ")");
      picked.push_back(found);
    }
  }

  const char* model_field = r.command == "fit" ? "model" : "best_model";
  for (const json* cp : picked) {
    const json& c = *cp;
    if (!c.is_object() || !c.contains("name") || !c["name"].is_string())
      throw InputError(path + ": a column without a \"name\", " + kExpected);
    const std::string name = c["name"].get<std::string>();
    const std::string at = path + ": column '" + name + "': ";
    std::string status = "unknown";
    if (r.command == "fit" && c.contains("status") && c["status"].is_string()) status = c["status"];
    if (r.command == "select" && c.contains("best_fit") && c["best_fit"].is_object() &&
        c["best_fit"].contains("status") && c["best_fit"]["status"].is_string())
      status = c["best_fit"]["status"];
    if (c.contains(model_field) && !c[model_field].is_string() && !c[model_field].is_null())
      throw InputError(at + "found \"" + model_field + "\": " + c[model_field].type_name() +
                       ", expected a model string such as \"WN(sigma2=1e-4)+RW(gamma2=1e-9)\"");
    if (!c.contains(model_field) || !c[model_field].is_string())
      throw InputError(at + "no fitted model (\"" + model_field + "\" is null; status " + status +
                       "); leave the column out with --columns");

    ExportColumn e;
    e.name = name;
    if (c.contains("n") && c["n"].is_number_integer()) e.n = c["n"].get<std::int64_t>();
    if (c.contains("freq") && c["freq"].is_number()) {
      e.freq = c["freq"].get<double>();
    } else if (o.rate) {
      e.freq = *o.rate;
    } else {
      throw InputError(at + "no sampling rate (\"freq\" is null); give --rate HZ, the rate its data were sampled at");
    }
    if (!(e.freq > 0.0)) throw InputError(at + "\"freq\" is not a positive rate in Hz");
    if (o.unit_free) {
      // The kind and unit only label the figures: what the column says, as written.
      try {
        e.kind = sensor_kind_of_column(name);
      } catch (const InputError&) {
        e.kind = SensorKind::kGyro;
      }
      e.unit = Unit{c.contains("unit") && c["unit"].is_string() ? c["unit"].get<std::string>() : std::string(), 1.0};
    } else {
      try {
        e.kind = o.sensor ? *o.sensor : sensor_kind_of_column(name);
      } catch (const InputError& err) {
        throw InputError(path + ": " + err.what());
      }
      e.unit = result_unit(c, e.kind, o, at);
    }
    const std::string spec = c[model_field].get<std::string>();
    try {
      e.model = parse_model(spec, ProcessContext{e.freq, true});
    } catch (const InputError& err) {
      throw InputError(at + "\"" + model_field + "\": " + err.what());
    }
    if (!e.model.fully_specified())
      throw InputError(at + "\"" + model_field + "\" '" + spec + "' does not give every parameter's value");
    e.theta = e.model.given_values();
    e.model = e.model.canonical(&e.theta);
    e.figures = figures_of(c);
    r.columns.push_back(std::move(e));
    r.statuses.push_back(status);
  }
  return r;
}

}  // namespace gmwm::io
