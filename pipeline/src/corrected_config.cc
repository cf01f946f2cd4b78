// The corrected simulator configuration of a gap study as a pipeline of named stages:
//   export_columns (final models + their figures against the data's Allan deviation)
//   -> render (the baseline's format, via render_export) -> read_back (the reader gap
//   uses) -> changes (input vs corrected fields) -> assess (gap left) -> header.
#include "gmwm/pipeline/corrected_config.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>

#include "gmwm/engine/error.h"
#include "gmwm/engine/noise_figures.h"
#include "gmwm/io/export.h"
#include "gmwm/io/export_text.h"
#include "gmwm/io/sim_config.h"
#include "config_edit.h"

namespace gmwm::pipeline {
using namespace io;  // the readers and writers this stage joins (signals, units, exports, configs)
namespace {

using export_text::num;

SensorKind kind_of(const std::string& column, const CorrectedConfigOptions& o) {
  return o.sensor ? *o.sensor : sensor_kind_of_column(column);
}

Unit unit_of(SensorKind kind, const CorrectedConfigOptions& o) {
  const auto it = o.units.find(kind);
  return it != o.units.end() ? it->second : si_unit(kind);
}

// Stage 1: every column's final model with the figures `export` would write for it: N, K
// and B read off the model's Allan deviation where it matches the data's, else the data's.
std::vector<ExportColumn> export_columns(const SignalSet& set, const GapStudy& study, const CorrectedConfigOptions& o) {
  std::vector<ExportColumn> cols;
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    const pipeline::GapColumnStudy& c = study.columns[k];
    ExportColumn e;
    e.name = c.name;
    e.kind = kind_of(c.name, o);
    e.freq = set.freq;
    e.n = c.wv.n;
    e.model = c.result.final_model;
    e.theta = c.result.final_theta;
    e.unit = unit_of(e.kind, o);
    const FigureReport figures = noise_figure_report(set.signals[k].values, set.freq, e.model, e.theta, nullptr);
    e.figures = export_figures(figures.chosen);
    cols.push_back(std::move(e));
  }
  return cols;
}

ExportFormat export_format(SimFormat f) {
  switch (f) {
    case SimFormat::kKalibr:
      return ExportFormat::kKalibr;
    case SimFormat::kGzSensors:
      return ExportFormat::kGzSdf;
    case SimFormat::kRotors:
      return ExportFormat::kRotors;
    case SimFormat::kDatasheet:
      break;  // Kalibr's N and K, then the datasheet's own text (corrected_config)
  }
  return ExportFormat::kKalibr;
}

// A datasheet's figures of each diagnosed sensor (SI): N and K as the Kalibr export
// combines them over the sensor's columns (their mean), B as the columns' mean, and the slowest Gauss-Markov bias's correlation time when
// every column of the sensor has one.
std::map<SensorKind, DatasheetFigures> datasheet_figures(const ExportResult& r) {
  std::map<SensorKind, DatasheetFigures> out;
  for (const KindExport& k : r.kinds) {
    if (k.columns.empty()) continue;
    DatasheetFigures d;
    d.white = k.combined.noise_density;
    d.walk = k.combined.random_walk;
    int count = 0, with_bias = 0;
    double T = 0.0;
    for (std::size_t c = 0; c < r.columns.size(); ++c) {
      const AxisNoise& a = r.columns[c];
      if (a.kind != k.kind) continue;
      ++count;
      d.instability += a.instability;
      if (!a.gauss_markov.empty()) {
        ++with_bias;
        T += a.gauss_markov.back().correlation_time;
      }
    }
    d.instability /= count;
    d.correlation_time = with_bias == count ? T / count : 0.0;
    out[k.kind] = d;
  }
  return out;
}

bool writes_correlation_time(const SimConfig& back, SensorKind kind) {
  const std::string name =
      std::string(kind == SensorKind::kGyro ? "gyroscope" : "accelerometer") + "/bias_correlation_time";
  return std::any_of(back.fields.begin(), back.fields.end(), [&](const ConfigField& f) { return f.name == name; });
}

// Stage 4: the fields of the input and of the corrected file, joined by name (input order,
// then fields only the corrected file has).
std::vector<ConfigChange> changes(const SimConfig& input, const SimConfig& corrected) {
  std::vector<ConfigChange> out;
  for (const ConfigField& f : input.fields) out.push_back({f.name, f.value, std::nan(""), f.unit, false});
  for (const ConfigField& f : corrected.fields) {
    auto it = std::find_if(out.begin(), out.end(), [&](const ConfigChange& c) { return c.field == f.name; });
    if (it == out.end())
      out.push_back({f.name, std::nan(""), f.value, f.unit, false});
    else
      it->corrected = f.value;
  }
  for (ConfigChange& c : out) {
    const bool both = std::isfinite(c.input) && std::isfinite(c.corrected);
    c.changed = !both ? std::isfinite(c.input) != std::isfinite(c.corrected)
                      : std::abs(c.corrected - c.input) >
                            kUnchangedRelative * std::max(std::abs(c.input), std::abs(c.corrected));
  }
  return out;
}

std::string effects_text(const gap::GapResult& g) {
  std::string s;
  for (const auto& d : g.step_details) s += (s.empty() ? "" : " + ") + d;
  return s.empty() ? "no effect added" : s;
}

std::string outside_text(const gap::GapAssessment& a) { return std::to_string(a.levels_outside) + " levels outside"; }

// Stage 6: the header: what changed and why, what the format cannot hold, the gap left.
std::vector<std::string> header_lines(const CorrectedConfig& c, const GapStudy& study, const SignalSet& set,
                                      const CorrectedConfigOptions& o) {
  std::vector<std::string> h;
  h.push_back("gmwm gap: the corrected " + c.format + " configuration for " + set.path +
              " (baseline: " + (o.baseline_path.empty() ? study.baseline_source : o.baseline_path) + ")");
  h.push_back(c.format == "model"
                  ? "Each column's line is the diagnosis' final model with its values (discrete, per sample, in the "
                    "data's unit): give it to 'gmwm gap --model' or 'gmwm export INPUT --model' for a simulator's file."
                  : "Each figure is what 'gmwm export' writes for the diagnosis' final model of the column (IEEE 952 "
                    "read-offs of the model's Allan deviation where it matches the data's, else the data's own).");
  int changed = 0;
  for (const ConfigChange& ch : c.changes) {
    if (!ch.changed) continue;
    ++changed;
    if (c.format == "model") {  // a column's whole model: its line below holds it
      h.push_back("changed: " + ch.field + "'s model (the diagnosis added or re-sized terms: its line below)");
      continue;
    }
    h.push_back("changed: " + ch.field + " " + (std::isfinite(ch.input) ? num(ch.input, 4) : std::string("(absent)")) +
                " -> " + (std::isfinite(ch.corrected) ? num(ch.corrected, 4) : std::string("(dropped)")) + " " +
                ch.unit);
  }
  if (changed == 0)
    h.push_back("changed: nothing (every figure within " + num(kUnchangedRelative * 100.0, 2) + "% of the input)");
  for (std::size_t k = 0; k < c.columns.size(); ++k) {
    const CorrectedColumn& col = c.columns[k];
    const gap::GapResult& g = study.columns[k].result;
    h.push_back("why, " + col.name + ": " + effects_text(g) + "; full model " + col.full.to_string(col.full_theta));
    for (const std::string& x : col.not_expressible) h.push_back("cannot express, " + col.name + ": " + x);
    for (const std::string& x : col.warnings) h.push_back("warning, " + col.name + ": " + x);
    h.push_back("gap left, " + col.name + ": input " + outside_text(col.before) + " (objective " +
                num(col.before.objective, 4) + ") -> this file " + outside_text(col.with_config) + " (objective " +
                num(col.with_config.objective, 4) + ") -> full model " + outside_text(col.with_full) + " (objective " +
                num(col.with_full.objective, 4) + ")");
  }
  return h;
}

std::string with_header(const std::string& format, const std::string& body, const std::vector<std::string>& h) {
  if (format == "gz-sdf" || format == "rotors") {
    std::string comment = "<!--\n";
    for (const auto& l : h) comment += "  " + export_text::xml_comment_text(l) + "\n";
    comment += "-->\n";
    // After an XML declaration, which must come first.
    if (body.rfind("<?xml", 0) == 0) {
      const std::size_t eol = body.find('\n');
      return body.substr(0, eol + 1) + comment + body.substr(eol + 1);
    }
    return comment + body;
  }
  // After an OpenCV-style "%YAML:1.0" first line (OpenVINS, VINS), which must come first.
  if (body.rfind("%YAML", 0) == 0) {
    const std::size_t eol = body.find('\n');
    return body.substr(0, eol + 1) + export_text::yaml_comments(h) + body.substr(eol + 1);
  }
  return export_text::yaml_comments(h) + body;
}

CorrectedConfig model_config(const SignalSet& set, const GapStudy& study, const CorrectedConfigOptions& o) {
  CorrectedConfig c;
  c.format = "model";
  std::string body;
  for (const pipeline::GapColumnStudy& s : study.columns) {
    CorrectedColumn col;
    col.name = s.name;
    col.full = s.result.final_model;
    col.full_theta = s.result.final_theta;
    col.expressible = col.full;
    col.expressible_theta = col.full_theta;
    if (s.result.assessor) {
      col.before = s.result.assessor->assess(s.baseline, s.theta);
      col.with_full = col.with_config = s.result.assessor->assess(col.full, col.full_theta);
    }
    body += s.name + ": " + col.full.to_string(col.full_theta) + "\n";
    c.changes.push_back({s.name, std::nan(""), std::nan(""), "model", !(s.result.steps.empty())});
    c.columns.push_back(std::move(col));
  }
  c.header = header_lines(c, study, set, o);
  c.content = with_header(c.format, body, c.header);
  return c;
}

// What a column's model holds that the corrected file cannot: the terms the format has no
// field for (a datasheet holds one bias figure, Kalibr none, a simulator one Gauss-Markov
// bias), each with why; terms counted in the white noise density.
std::vector<std::string> not_expressible(const AxisNoise& a, const SimConfig& back, bool datasheet, bool kalibr) {
  std::vector<std::string> out = a.others;
  // A datasheet's bias figure without a correlation time is a flicker floor: the model's
  // FLICKER is what it holds.
  if (datasheet && !writes_correlation_time(back, a.kind))
    std::erase_if(out, [](const std::string& x) { return x.rfind("FLICKER(", 0) == 0; });
  if (datasheet)
    for (std::size_t i = 0; i < a.gauss_markov.size(); ++i) {
      const bool written = i + 1 == a.gauss_markov.size() && writes_correlation_time(back, a.kind);
      if (!written)
        out.push_back(
            a.gauss_markov[i].text + " (a Gauss-Markov bias, correlation time " +
            num(a.gauss_markov[i].correlation_time, 3) + " s: the datasheet holds one bias figure, " +
            (i + 1 == a.gauss_markov.size() ? std::string("here a flicker floor") : std::string("the slowest")) + ")");
    }
  else if (kalibr)
    for (const GaussMarkovNoise& gm : a.gauss_markov)
      out.push_back(gm.text + " (a Gauss-Markov bias, correlation time " + num(gm.correlation_time, 3) +
                    " s: Kalibr holds white noise and a random walk only)");
  else if (a.gauss_markov.size() > 1)
    for (std::size_t i = 0; i + 1 < a.gauss_markov.size(); ++i)
      out.push_back(a.gauss_markov[i].text +
                    " (the simulator holds one Gauss-Markov bias: the "
                    "slowest is written)");
  for (const std::string& x : a.absorbed) out.push_back(x + ": counted in the white noise density");
  return out;
}

// The names a format gives a sensor's figures.
const char* sensor_word(SensorKind k) { return k == SensorKind::kGyro ? "gyroscope" : "accelerometer"; }
const char* sdf_element(SensorKind k) { return k == SensorKind::kGyro ? "angular_velocity" : "linear_acceleration"; }

// A part of the corrected file written as one: an axis of a gz-sensors sensor (its <noise>
// block), else a sensor's figures (Kalibr, RotorS and a datasheet hold one per sensor, and
// so does gz-sensors when a column has no axis letter to place it).
struct FileUnit {
  SensorKind kind = SensorKind::kGyro;
  char axis = 0;                     ///< 'x', 'y', 'z': a gz-sensors axis; 0: the sensor's figures
  std::vector<std::size_t> columns;  ///< the study's columns it holds
  CorrectedVerdict verdict = CorrectedVerdict::kWritten;
  std::string why;
  std::vector<detail::ConfigEdit> edits;
  std::vector<std::string> notes;  ///< figures it no longer writes, and why
};

// The figures of `u` the diagnosis sizes, by name: noise only, never a constant offset
// (gz-sensors mean, bias_mean, bias_stddev, RotorS *TurnOnBiasSigma: invisible to a
// wavelet variance, the input's are kept) nor the rate. gz-sensors' precision is one: the
// output's rounding noise is part of the data's white noise, which the corrected stddev
// holds (keeping both would count it twice), so a written axis drops it.
bool holds(const FileUnit& u, SimFormat format, const std::string& name) {
  const std::string sensor = sensor_word(u.kind);
  switch (format) {
    case SimFormat::kKalibr:
      return name == sensor + "_noise_density" || name == sensor + "_random_walk";
    case SimFormat::kRotors:
      return name == sensor + "NoiseDensity" || name == sensor + "RandomWalk" || name == sensor + "BiasCorrelationTime";
    case SimFormat::kDatasheet:
      return name.rfind(sensor + "/", 0) == 0;
    case SimFormat::kGzSensors:
      break;
  }
  const std::string element = std::string(sdf_element(u.kind)) + "/";
  if (name.rfind(element, 0) != 0 || name.size() < element.size() + 8) return false;
  const char axis = name[element.size()];
  if ((u.axis && axis != u.axis) || name.compare(element.size() + 1, 7, "/noise/") != 0) return false;
  const std::string leaf = name.substr(element.size() + 8);
  return leaf == "stddev" || leaf == "dynamic_bias_stddev" || leaf == "dynamic_bias_correlation_time" ||
         leaf == "precision";
}

// The block a figure new to the file joins (its siblings' prefix): a gz-sensors axis's
// <noise>, a datasheet's sensor; RotorS' plugin and Kalibr's map as a whole.
std::string block_of(SimFormat format, const std::string& name) {
  if (format == SimFormat::kGzSensors || format == SimFormat::kDatasheet) return name.substr(0, name.rfind('/') + 1);
  return "";
}

bool differs(double a, double b) { return std::abs(a - b) > kUnchangedRelative * std::max(std::abs(a), std::abs(b)); }

const ConfigField* field_named(const SimConfig& c, const std::string& name) {
  const auto it = std::find_if(c.fields.begin(), c.fields.end(), [&](const ConfigField& f) { return f.name == name; });
  return it == c.fields.end() ? nullptr : &*it;
}

std::string names_of(const GapStudy& study, const std::vector<std::size_t>& columns) {
  std::string s;
  for (std::size_t k : columns) s += (s.empty() ? "" : ", ") + study.columns[k].name;
  return s;
}

// Stage 1b: the parts of the file the study's columns hold. A figure that holds a sensor's
// three axes is written only when the run took all three, or took the record's every column
// (--columns not given): otherwise it would hand a left-out axis another axis's figure.
std::vector<FileUnit> file_units(const GapStudy& study, SimFormat format, const CorrectedConfigOptions& o) {
  std::vector<FileUnit> units;
  for (SensorKind kind : {SensorKind::kGyro, SensorKind::kAccel}) {
    std::vector<std::size_t> columns;
    std::string axes;
    for (std::size_t k = 0; k < study.columns.size(); ++k)
      if (kind_of(study.columns[k].name, o) == kind) {
        columns.push_back(k);
        axes += column_axis(study.columns[k].name);
      }
    if (columns.empty()) continue;
    std::string sorted = axes;
    std::sort(sorted.begin(), sorted.end());
    const bool distinct =
        sorted.find('\0') == std::string::npos && std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end();
    if (format == SimFormat::kGzSensors && distinct) {
      for (std::size_t i = 0; i < columns.size(); ++i) {
        FileUnit u;
        u.kind = kind;
        u.axis = axes[i];
        u.columns = {columns[i]};
        units.push_back(std::move(u));
      }
      continue;
    }
    FileUnit u;
    u.kind = kind;
    u.columns = columns;
    if (o.columns_chosen && sorted != "xyz") {
      u.verdict = CorrectedVerdict::kKeptSubset;
      u.why = std::string("the ") + sensor_word(kind) + "'s figures hold its three axes and --columns diagnosed " +
              names_of(study, columns) + " only: the input's are kept (diagnose the three axes to change them)";
    }
    units.push_back(std::move(u));
  }
  return units;
}

// Stage 2: the export's figures for the diagnosed columns, in the input's format, read back
// with the reader gap uses: per `aggregation` (a figure per axis, or the sensor's mean).
struct Proposed {
  SimConfig config;
  std::vector<AxisNoise> noise;  ///< per exported column
};

const AxisNoise* noise_of(const Proposed& p, const std::string& column) {
  for (const AxisNoise& a : p.noise)
    if (a.column == column) return &a;
  return nullptr;
}

Proposed propose(const SignalSet& set, const SimConfig& input, const std::vector<ExportColumn>& cols,
                 Aggregation aggregation, const CorrectedConfigOptions& o) {
  ExportOptions eo;
  eo.format = export_format(input.format);
  eo.aggregation = aggregation;
  eo.missing = MissingSensor::kZero;  // a sensor without a column is not written from it
  const ExportResult r = render_export(cols, eo, "gmwm gap of " + set.path);
  const std::string name = "the corrected configuration";
  Proposed p{
      input.format == SimFormat::kDatasheet
          ? parse_datasheet_yaml(write_datasheet_yaml(input, datasheet_figures(r), set.freq), name, set.freq, o.units)
      : input.format == SimFormat::kKalibr ? parse_kalibr_imu_yaml(r.content, name, set.freq, o.units)
                                           : parse_gazebo_sdf(r.content, name, set.freq, o.units),
      r.columns};
  return p;
}

// gz-sensors' export per axis needs the three axes of a sensor: the axes the study has no
// column for get the input's own model of them (their figures are not written).
std::vector<ExportColumn> with_every_axis(std::vector<ExportColumn> cols, const SimConfig& input) {
  const std::size_t diagnosed = cols.size();
  for (SensorKind kind : {SensorKind::kGyro, SensorKind::kAccel}) {
    const auto first = std::find_if(cols.begin(), cols.begin() + static_cast<std::ptrdiff_t>(diagnosed),
                                    [&](const ExportColumn& c) { return c.kind == kind; });
    if (first == cols.begin() + static_cast<std::ptrdiff_t>(diagnosed)) continue;
    const ExportColumn like = *first;
    for (const char axis : {'x', 'y', 'z'}) {
      if (std::any_of(cols.begin(), cols.end(),
                      [&](const ExportColumn& c) { return c.kind == kind && column_axis(c.name) == axis; }))
        continue;
      ExportColumn e = like;
      e.name = std::string(to_string(kind)) + "_" + axis;
      const auto alike = input.models.find(kind);
      const auto own = input.axis_models.find(e.name);
      if (alike != input.models.end() || own != input.axis_models.end()) {
        e.model = alike != input.models.end() ? alike->second : own->second;
        e.theta = e.model.given_values();
        e.figures.reset();
      }
      cols.push_back(std::move(e));
    }
  }
  return cols;
}

// Stage 3: the edits that write unit `u`'s figures from `proposed` into the input's text:
// a figure both hold and that differs is replaced where the input wrote it, one only the
// proposal has is added after its block's last line, one only the input has is removed.
bool unit_edits(const SimConfig& input, const SimConfig& proposed, FileUnit& u) {
  const SimFormat format = input.format;
  for (const ConfigField& p : proposed.fields) {
    if (!holds(u, format, p.name)) continue;
    if (const ConfigField* in = field_named(input, p.name)) {
      if (differs(in->value, p.value)) u.edits.push_back({detail::ConfigEdit::kSet, in, "", p.text});
      continue;
    }
    const std::string block = block_of(format, p.name);
    const ConfigField* anchor = nullptr;
    for (const ConfigField& f : input.fields)
      if (f.name.rfind(block, 0) == 0 && f.line > 0 && (!anchor || f.line > anchor->line) &&
          (format != SimFormat::kKalibr || f.name != "update_rate"))
        anchor = &f;
    if (!anchor) return false;
    u.edits.push_back({detail::ConfigEdit::kInsert, anchor, detail::config_key(p.name), p.text});
  }
  for (const ConfigField& in : input.fields) {
    if (!holds(u, format, in.name) || field_named(proposed, in.name)) continue;
    u.edits.push_back({detail::ConfigEdit::kRemove, &in, "", ""});
    if (detail::config_key(in.name) == "precision" && in.value != 0.0)
      u.notes.push_back(in.name + " " + export_text::real(in.value) + " " + in.unit +
                        " not written: the output's rounding noise is part of the data's white noise, which the "
                        "corrected stddev holds");
  }
  return true;
}

detail::ConfigSyntax syntax_of(SimFormat f) {
  return f == SimFormat::kGzSensors || f == SimFormat::kRotors ? detail::ConfigSyntax::kXml
                                                               : detail::ConfigSyntax::kYaml;
}

// The input's figure a unit's edits moved though the unit does not hold it ("" when none):
// a YAML anchor written on one figure and aliased by another (`gyroscope_random_walk: &a
// 1e-5`, `accelerometer_noise_density: *a`) would carry a gyroscope's correction into an
// accelerometer nobody diagnosed. An edited text that no longer reads is such a move too.
std::string moved_elsewhere(const SimConfig& input, const FileUnit& u, const std::string& text,
                            const std::function<SimConfig(const std::string&)>& read_back) {
  SimConfig back;
  try {
    back = read_back(text);
  } catch (const InputError&) {
    return "the file as a whole (it no longer reads)";
  }
  for (const ConfigField& in : input.fields) {
    if (holds(u, input.format, in.name)) continue;
    const ConfigField* b = field_named(back, in.name);
    if (!b || differs(in.value, b->value)) return in.name;
  }
  return "";
}

// The units' edits, each checked alone against the input's text: a unit whose figures are
// not where the input says, or whose edits would move a figure it does not hold, keeps the
// input's.
void plan_edits(const SimConfig& input, const std::vector<const SimConfig*>& proposed, std::vector<FileUnit>& units,
                const std::function<SimConfig(const std::string&)>& read_back) {
  for (std::size_t i = 0; i < units.size(); ++i) {
    FileUnit& u = units[i];
    if (u.verdict != CorrectedVerdict::kWritten) continue;
    const bool placed = unit_edits(input, *proposed[i], u);
    const std::optional<std::string> text =
        placed ? detail::apply_config_edits(input.text, syntax_of(input.format), u.edits) : std::nullopt;
    const std::string moved = text && !u.edits.empty() ? moved_elsewhere(input, u, *text, read_back) : "";
    if (!text || !moved.empty()) {
      u.edits.clear();
      u.notes.clear();
      u.verdict = CorrectedVerdict::kKeptUnplaced;
      u.why = text ? "writing its figures would change " + moved +
                         " too (the input's text shares them: a YAML anchor and alias?): the input's are kept"
                   : "its figures are not where the input's text has them (a flow-style map?): the input's are kept";
    } else if (u.edits.empty()) {
      u.verdict = CorrectedVerdict::kUnchanged;
    }
  }
}

// The input's text with the edits of every unit written.
std::string edited_text(const SimConfig& input, const std::vector<FileUnit>& units) {
  std::vector<detail::ConfigEdit> all;
  for (const FileUnit& u : units)
    if (u.verdict == CorrectedVerdict::kWritten) all.insert(all.end(), u.edits.begin(), u.edits.end());
  const std::optional<std::string> text = detail::apply_config_edits(input.text, syntax_of(input.format), all);
  if (!text) throw InputError("--corrected: the corrected figures could not be placed in the input's text");
  return *text;
}

// A header an earlier `gap --corrected` wrote at the top (the input is a corrected file):
// taken out, so that the new header replaces it rather than stacking on it.
std::string without_previous_header(const std::string& text, detail::ConfigSyntax syntax) {
  const std::string mark = "gmwm gap: the corrected ";
  std::size_t at = 0;
  if (text.rfind("<?xml", 0) == 0 || text.rfind("%YAML", 0) == 0) at = text.find('\n') + 1;
  if (at == 0 && text.rfind("<?xml", 0) == 0) return text;
  if (syntax == detail::ConfigSyntax::kYaml) {
    if (text.compare(at, 2 + mark.size(), "# " + mark) != 0) return text;
    std::size_t end = at;
    while (end < text.size() && text[end] == '#')
      end = text.find('\n', end) == std::string::npos ? text.size() : text.find('\n', end) + 1;
    return text.substr(0, at) + text.substr(end);
  }
  if (text.compare(at, 4, "<!--") != 0) return text;
  const std::size_t first = text.find_first_not_of(" \t\r\n", at + 4), close = text.find("-->", at);
  if (first == std::string::npos || close == std::string::npos || text.compare(first, mark.size(), mark) != 0)
    return text;
  const std::size_t end = text.find('\n', close);
  return text.substr(0, at) + text.substr(end == std::string::npos ? text.size() : end + 1);
}

}  // namespace

const char* to_string(CorrectedVerdict v) {
  switch (v) {
    case CorrectedVerdict::kWritten:
      return "written";
    case CorrectedVerdict::kUnchanged:
      return "unchanged";
    case CorrectedVerdict::kKeptSubset:
      return "kept: holds axes not diagnosed";
    case CorrectedVerdict::kKeptUnplaced:
      return "kept: not found in the input's text";
  }
  return "written";
}

namespace {

// Stage 2 for every unit: the proposal its figures come from. gz-sensors' axes get their own
// figures (real units' axes differ: the ADIS16405 accelerometers' N spans 1.5x - 1.7x
// between axes, so one figure for three cannot be within 15% of each); a sensor's figures
// are the mean over its diagnosed columns.
struct Proposals {
  Proposed mean;
  std::optional<Proposed> per_axis;
  std::vector<const SimConfig*> of_unit;  ///< per unit
  const AxisNoise& noise(const std::vector<FileUnit>& units, std::size_t k, const std::string& column) const {
    for (std::size_t i = 0; i < units.size(); ++i)
      if (std::find(units[i].columns.begin(), units[i].columns.end(), k) != units[i].columns.end() && units[i].axis &&
          per_axis)
        if (const AxisNoise* a = noise_of(*per_axis, column)) return *a;
    return *noise_of(mean, column);
  }
};

Proposals proposals(const SignalSet& set, const SimConfig& input, const std::vector<ExportColumn>& cols,
                    const std::vector<FileUnit>& units, const CorrectedConfigOptions& o) {
  Proposals p{propose(set, input, cols, Aggregation::kMean, o), std::nullopt, {}};
  std::vector<ExportColumn> axis_cols;
  for (const FileUnit& u : units)
    if (u.axis)
      for (std::size_t k : u.columns) axis_cols.push_back(cols[k]);
  if (!axis_cols.empty()) p.per_axis = propose(set, input, with_every_axis(axis_cols, input), Aggregation::kPerAxis, o);
  for (const FileUnit& u : units) p.of_unit.push_back(u.axis ? &p.per_axis->config : &p.mean.config);
  return p;
}

// Stage 5: a column's gap left with the input, with the corrected file and with the full
// model, on the diagnosis' own yardstick.
CorrectedColumn assess_column(const GapColumnStudy& s, const SimConfig& back, const AxisNoise& a, const FileUnit& unit,
                              const CorrectedConfigOptions& o) {
  CorrectedColumn col;
  col.name = s.name;
  col.full = s.result.final_model;
  col.full_theta = s.result.final_theta;
  col.not_expressible =
      not_expressible(a, back, back.format == SimFormat::kDatasheet, back.format == SimFormat::kKalibr);
  col.verdict = unit.verdict;
  col.why = unit.why;
  const auto expressible = config_baseline(back, kind_of(s.name, o), s.name, s.wv.n);
  if (expressible) {
    col.expressible = expressible->model;
    col.expressible_theta = expressible->theta;
  }
  if (s.result.assessor) {
    col.before = s.result.assessor->assess(s.baseline, s.theta);
    col.with_full = s.result.assessor->assess(col.full, col.full_theta);
    if (expressible) col.with_config = s.result.assessor->assess(col.expressible, col.expressible_theta);
    col.warnings = corrected_column_warnings(col);
  }
  return col;
}

// What the header says of the parts of the file left as the input wrote them.
std::vector<std::string> kept_lines(const GapStudy& study, const std::vector<FileUnit>& units, SimFormat format) {
  std::vector<std::string> out;
  for (const FileUnit& u : units) {
    for (const std::string& n : u.notes) out.push_back(n);
    if (!u.why.empty()) out.push_back("kept, " + names_of(study, u.columns) + ": " + u.why);
  }
  std::string untouched;
  for (SensorKind kind : {SensorKind::kGyro, SensorKind::kAccel})
    for (const char axis : {'x', 'y', 'z'}) {
      const bool written = std::any_of(
          units.begin(), units.end(), [&](const FileUnit& u) { return u.kind == kind && (!u.axis || u.axis == axis); });
      if (written) continue;
      const std::string part = format == SimFormat::kGzSensors ? std::string(sdf_element(kind)) + "/" + axis
                                                               : std::string(sensor_word(kind));
      if (untouched.find(part) == std::string::npos) untouched += (untouched.empty() ? "" : ", ") + part;
    }
  if (!untouched.empty()) out.push_back("not diagnosed, as the input wrote it: " + untouched);
  return out;
}

}  // namespace

// A column the file makes worse than its input, or more optimistic than the data's model:
// never silently (issue 43, item 6).
std::vector<std::string> corrected_column_warnings(const CorrectedColumn& col) {
  std::vector<std::string> w;
  if (col.expressible.num_components() == 0 || col.verdict != CorrectedVerdict::kWritten) return w;
  const gap::GapAssessment &in = col.before, &file = col.with_config, &full = col.with_full;
  const bool objective_worse = file.objective > in.objective * (1.0 + kWorseThanInputTolerance);
  if (objective_worse || file.levels_outside > in.levels_outside) {
    const std::string levels =
        "levels outside " + std::to_string(in.levels_outside) + " -> " + std::to_string(file.levels_outside);
    const std::string objective = "objective " + num(in.objective, 4) + " -> " + num(file.objective, 4) +
                                  " (full model " + num(full.objective, 4) + ")";
    w.push_back((objective_worse ? "this file is worse than its input here: " + objective + ", " + levels
                                 : "this file leaves more levels outside the model's band than its input here: " +
                                       levels + ", though its " + objective) +
                (col.not_expressible.empty()
                     ? std::string()
                     : "; the format cannot hold what the data's model needs (" +
                           std::to_string(col.not_expressible.size()) + " term(s) not expressible, below)") +
                ": keep the input's figures, or simulate the full model");
  }
  if (std::isfinite(file.navigation_rms) && std::isfinite(full.navigation_rms) && full.navigation_rms > 0.0 &&
      file.navigation_rms < (1.0 - kOptimisticShare) * full.navigation_rms)
    w.push_back(
        "this file is more optimistic than the data's model: its integrated error after the navigation "
        "horizon is " +
        num(file.navigation_rms, 3) + " against the full model's " + num(full.navigation_rms, 3) + " (" +
        num(full.navigation_rms / file.navigation_rms, 3) +
        "x smaller): a filter tuned from it trusts the IMU too far");
  return w;
}

CorrectedConfig corrected_config(const SignalSet& set, const GapStudy& study, const GapStudyOptions& options,
                                 const CorrectedConfigOptions& o) {
  const auto* config = std::get_if<pipeline::ConfigBaseline>(&options.baseline);
  if (!config) return model_config(set, study, o);
  if (!set.freq_known)
    throw InputError("--corrected: the data's sampling rate is needed to write noise densities (give --freq)");
  const SimConfig& input = config->config;
  CorrectedConfig c;
  c.format = to_string(input.format);
  // Stages 1-3: the final models' figures in the input's format, and where each goes.
  std::vector<FileUnit> units = file_units(study, input.format, o);
  const Proposals p = proposals(set, input, export_columns(set, study, o), units, o);
  // A corrected text read back exactly as gap reads a baseline.
  const std::string name = "the corrected configuration";
  const auto read_back = [&](const std::string& text) {
    return input.format == SimFormat::kDatasheet ? parse_datasheet_yaml(text, name, set.freq, o.units)
           : input.format == SimFormat::kKalibr  ? parse_kalibr_imu_yaml(text, name, set.freq, o.units, input.imu)
                                                 : parse_gazebo_sdf(text, name, set.freq, o.units);
  };
  plan_edits(input, p.of_unit, units, read_back);
  // Stage 4: the input's text with the figures written, read back.
  const detail::ConfigSyntax syntax = syntax_of(input.format);
  const std::string body = without_previous_header(edited_text(input, units), syntax);
  const SimConfig back = read_back(body);
  c.changes = changes(input, back);
  // Stage 5: each column's gap left with the corrected file and with the full model.
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    const auto u = std::find_if(units.begin(), units.end(), [&](const FileUnit& x) {
      return std::find(x.columns.begin(), x.columns.end(), k) != x.columns.end();
    });
    c.columns.push_back(assess_column(study.columns[k], back, p.noise(units, k, study.columns[k].name), *u, o));
  }
  c.header = header_lines(c, study, set, o);
  const std::vector<std::string> kept = kept_lines(study, units, input.format);
  c.header.insert(c.header.begin() + 2, kept.begin(), kept.end());
  c.content = with_header(c.format, body, c.header);
  return c;
}

}  // namespace gmwm::pipeline
