// The corrected simulator configuration of a gap study as a pipeline of named stages:
//   export_columns (final models + their figures against the data's Allan deviation)
//   -> render (the baseline's format, via render_export) -> read_back (the reader gap
//   uses) -> changes (input vs corrected fields) -> assess (gap left) -> header.
#include "gmwm/pipeline/corrected_config.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "gmwm/engine/error.h"
#include "gmwm/engine/noise_figures.h"
#include "gmwm/io/export.h"
#include "gmwm/io/export_text.h"
#include "gmwm/io/sim_config.h"

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

// The input's constant offsets in a simulator's file, kept: gz-sensors <mean>, <bias_mean>,
// <bias_stddev> and RotorS *TurnOnBiasSigma are constants within a run, invisible to a
// wavelet variance, so the diagnosis has nothing to say about them and the export's 0 must
// not replace the user's value. A field is the input's path ("angular_velocity/x/noise/
// bias_mean") or RotorS parameter; its element in the export's text gets the input's value.
// <precision> is not kept: its rounding noise is part of the data's white noise, which the
// corrected <stddev> already holds (keeping both would count it twice); a note says so.
void keep_constant_offsets(const SimConfig& input, ExportResult& r, std::vector<std::string>& notes) {
  auto leaf_of = [](const std::string& name) { return name.substr(name.rfind('/') + 1); };
  // The first `tag` at or after `from` outside an XML comment (the export's comments name
  // elements too).
  auto find_tag = [&](const std::string& tag, std::size_t from) {
    for (std::size_t at = r.content.find(tag, from); at != std::string::npos; at = r.content.find(tag, at + 1)) {
      const std::size_t open = r.content.rfind("<!--", at), close = r.content.rfind("-->", at);
      if (open == std::string::npos || (close != std::string::npos && close > open)) return at;
    }
    return std::string::npos;
  };
  auto set_value = [&](std::size_t from, std::size_t to, const std::string& leaf, double value) {
    const std::string open = "<" + leaf + ">", close = "</" + leaf + ">";
    const std::size_t at = find_tag(open, from);
    if (at == std::string::npos || at >= to) return false;
    const std::size_t v = at + open.size(), end = r.content.find(close, v);
    if (end == std::string::npos) return false;
    r.content.replace(v, end - v, export_text::real(value));
    return true;
  };
  for (const ConfigField& f : input.fields) {
    const std::string leaf = leaf_of(f.name);
    if (input.format == SimFormat::kRotors) {
      if (f.name.size() >= 15 && f.name.compare(f.name.size() - 15, 15, "TurnOnBiasSigma") == 0)
        set_value(0, r.content.size(), f.name, f.value);
      continue;
    }
    if (leaf == "precision" && f.value != 0.0) {
      notes.push_back(f.name + " " + export_text::real(f.value) + " " + f.unit +
                      " not written: the output's rounding noise is part of the data's white noise, which the "
                      "corrected stddev holds");
      continue;
    }
    if (leaf != "mean" && leaf != "bias_mean" && leaf != "bias_stddev") continue;
    // "angular_velocity/x/noise/bias_mean": the block of that sensor and axis.
    const std::size_t slash1 = f.name.find('/'), slash2 = f.name.find('/', slash1 + 1);
    if (slash1 == std::string::npos || slash2 == std::string::npos) continue;
    const std::size_t block = find_tag("<" + f.name.substr(0, slash1) + ">", 0);
    if (block == std::string::npos) continue;
    const std::size_t axis = find_tag("<" + f.name.substr(slash1 + 1, slash2 - slash1 - 1) + ">", block);
    if (axis == std::string::npos) continue;
    const std::size_t noise = find_tag("<noise", axis), end = find_tag("</noise>", noise);
    if (noise != std::string::npos && end != std::string::npos) set_value(noise, end, leaf, f.value);
  }
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

// A simulator's file holds both sensors: a sensor with no column in the study keeps the
// input's noise, written from the input's own model of it (per axis when the input's axes
// differ), its figures read off that model's Allan deviation over the record's length.
// Appended after the study's columns, so their indices stay those of the study.
void add_undiagnosed_kinds(const SimConfig& config, const SignalSet& set, std::vector<ExportColumn>& cols,
                           const CorrectedConfigOptions& o) {
  const std::int64_t n = cols.empty() ? 0 : cols.front().n;
  for (SensorKind kind : {SensorKind::kGyro, SensorKind::kAccel}) {
    if (std::any_of(cols.begin(), cols.end(), [&](const ExportColumn& c) { return c.kind == kind; })) continue;
    auto add = [&](const std::string& name, const Model& m) {
      ExportColumn e;
      e.name = name;
      e.kind = kind;
      e.freq = set.freq;
      e.n = n;
      e.model = m;
      e.theta = m.given_values();
      e.unit = unit_of(kind, o);
      cols.push_back(std::move(e));
    };
    // One column per axis (a per-axis file needs x, y and z), the kind's model on each when
    // the input's axes are alike.
    const auto alike = config.models.find(kind);
    for (const char axis : {'x', 'y', 'z'}) {
      const std::string name = std::string(to_string(kind)) + "_" + axis;
      if (alike != config.models.end())
        add(name, alike->second);
      else if (const auto it = config.axis_models.find(name); it != config.axis_models.end())
        add(name, it->second);
    }
  }
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

// A Kalibr file holds both sensors; a sensor with no column in the study keeps the input's
// figures (the export writes 0 for it): its lines are rewritten with the input's values.
void keep_undiagnosed_kinds(const SimConfig& input, ExportResult& r) {
  for (SensorKind kind : {SensorKind::kGyro, SensorKind::kAccel}) {
    const KindExport* k = export_text::find_kind(r, kind);
    if (k && !k->columns.empty()) continue;
    const std::string prefix = kind == SensorKind::kGyro ? "gyroscope_" : "accelerometer_";
    for (const ConfigField& f : input.fields) {
      if (f.name.rfind(prefix, 0) != 0) continue;
      const std::size_t at = r.content.find("\n" + f.name + ": ");
      if (at == std::string::npos) continue;
      const std::size_t from = at + 1 + f.name.size() + 2, to = r.content.find_first_of(" \n", from);
      r.content.replace(from, to - from, export_text::real(f.value));
    }
    // The export's header line "No ... column in the source: ... written as 0" no longer holds.
    const std::string word = kind == SensorKind::kGyro ? "gyroscope" : "accelerometer";
    const std::size_t line = r.content.find("# No " + word + " column in the source");
    const std::string kept = "# No " + word + " column diagnosed: its figures are the input's\n";
    if (line != std::string::npos)
      r.content.replace(line, r.content.find('\n', line) + 1 - line, kept);
    else
      r.content += kept;
  }
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

}  // namespace

CorrectedConfig corrected_config(const SignalSet& set, const GapStudy& study, const GapStudyOptions& options,
                                 const CorrectedConfigOptions& o) {
  const auto* config = std::get_if<pipeline::ConfigBaseline>(&options.baseline);
  if (!config) return model_config(set, study, o);
  if (!set.freq_known)
    throw InputError("--corrected: the data's sampling rate is needed to write noise densities (give --freq)");
  CorrectedConfig c;
  c.format = to_string(config->config.format);
  // Stages 1-2: the final models in the baseline's format. gz-sensors holds a block per
  // axis: each axis gets its own figures when every axis of the sensor was diagnosed (real
  // units' axes differ: the ADIS16405 accelerometers' N spans 1.5x - 1.7x between axes, so
  // one figure for three cannot be within 15% of each); else the sensor's mean.
  ExportOptions eo;
  eo.format = export_format(config->config.format);
  eo.aggregation = eo.format == ExportFormat::kGzSdf ? Aggregation::kPerAxis : Aggregation::kMean;
  // A sensor without a diagnosed column keeps the input's figures (keep_undiagnosed_kinds and
  // add_undiagnosed_kinds): the export's zeros are placeholders replaced below.
  eo.missing = MissingSensor::kZero;
  std::vector<ExportColumn> cols = export_columns(set, study, o);
  if (config->config.format == SimFormat::kGzSensors || config->config.format == SimFormat::kRotors)
    add_undiagnosed_kinds(config->config, set, cols, o);
  ExportResult r;
  std::vector<std::string> notes;
  try {
    r = render_export(cols, eo, "gmwm gap of " + set.path);
  } catch (const InputError&) {
    if (eo.aggregation != Aggregation::kPerAxis) throw;
    // Not every axis of a sensor has a column: one figure per sensor, said in the header.
    eo.aggregation = Aggregation::kMean;
    r = render_export(cols, eo, "gmwm gap of " + set.path);
    notes.push_back(
        "not every axis of a sensor was diagnosed: the diagnosed columns' mean is written for all three "
        "axes");
  }
  const bool datasheet = config->config.format == SimFormat::kDatasheet;
  if (datasheet)
    r.content = write_datasheet_yaml(config->config, datasheet_figures(r), set.freq);
  else if (eo.format == ExportFormat::kKalibr)
    keep_undiagnosed_kinds(config->config, r);
  else
    keep_constant_offsets(config->config, r, notes);
  // Stage 3: read back exactly as gap reads a baseline.
  const std::string name = "the corrected configuration";
  const SimConfig back = datasheet ? parse_datasheet_yaml(r.content, name, set.freq, o.units)
                         : eo.format == ExportFormat::kKalibr
                             ? parse_kalibr_imu_yaml(r.content, name, set.freq, o.units)
                             : parse_gazebo_sdf(r.content, name, set.freq, o.units);
  c.changes = changes(config->config, back);
  // Stage 5: each column's gap left with the corrected file and with the full model.
  for (std::size_t k = 0; k < study.columns.size(); ++k) {
    const pipeline::GapColumnStudy& s = study.columns[k];
    CorrectedColumn col;
    col.name = s.name;
    col.full = s.result.final_model;
    col.full_theta = s.result.final_theta;
    const AxisNoise& a = r.columns[k];
    col.not_expressible = not_expressible(a, back, datasheet, eo.format == ExportFormat::kKalibr);
    const auto expressible = pipeline::config_baseline(back, kind_of(s.name, o), s.name, s.wv.n);
    if (expressible) {
      col.expressible = expressible->model;
      col.expressible_theta = expressible->theta;
    }
    if (s.result.assessor) {
      col.before = s.result.assessor->assess(s.baseline, s.theta);
      col.with_full = s.result.assessor->assess(col.full, col.full_theta);
      if (expressible) col.with_config = s.result.assessor->assess(col.expressible, col.expressible_theta);
    }
    c.columns.push_back(std::move(col));
  }
  c.header = header_lines(c, study, set, o);
  c.header.insert(c.header.begin() + 2, notes.begin(), notes.end());
  c.content = with_header(c.format, r.content, c.header);
  return c;
}

}  // namespace gmwm::pipeline
