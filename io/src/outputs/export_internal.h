#pragma once
// Internals shared by the export renderers (io/src/export_*.cc): number and comment
// formatting, the SI unit names of each sensor kind, and one render function per format.
// render_export (export_format.cc) builds the ExportResult's figures and header
// (export_noise.cc), then calls the format's renderer for the text.

#include <string_view>
#include <string>
#include <vector>

#include "gmwm/io/export.h"
#include "gmwm/io/export_text.h"

namespace gmwm::io::export_detail {

// The text helpers (gmwm/io/export_text.h), by their short names here.
using export_text::find_kind;
using export_text::num;
using export_text::real;
using export_text::xml_comment;
using export_text::xml_comment_text;
using export_text::yaml_comments;

/// SI unit names of a sensor kind.
struct SiNames {
  const char* value;    ///< "rad/s", "m/s^2"
  const char* density;  ///< white noise density "rad/s/sqrt(Hz)", "m/s^2/sqrt(Hz)"
  const char* walk;     ///< random walk / bias driving density "rad/s^2/sqrt(Hz)", "m/s^3/sqrt(Hz)"
};
SiNames si_names(SensorKind kind);

/// The figures of `kind` to write in a one-value-per-sensor field: the aggregate, or zeros
/// when the kind is absent.
WrittenNoise combined_or_zero(const ExportResult& r, SensorKind kind);
/// True when a sensor kind's fields are written: the source has its columns, or the options
/// ask for zeros in their place (MissingSensor::kZero); false: left out (--partial).
bool writes_kind(const ExportOptions& o, const ExportResult& r, SensorKind kind);

/// True for the simulators (gz-sdf, rotors), which model one Gauss-Markov bias per axis
/// instead of a random walk.
bool simulates_bias(ExportFormat f);

/// A random walk K has no exact form in the simulators' Gauss-Markov bias: it is written as
/// a bias driven by K with a correlation time T this many times the record's length.
/// Over a lag t the bias then drifts with variance K^2 T (1 - exp(-t/T)) = K^2 t (1 - t/(2T)
/// + ...), i.e. within t/(2T) <= 1/2000 = 0.05% of the random walk's K^2 t over the whole
/// record (and less at shorter scales), while the stationary variance K^2 T / 2 it would
/// reach is never approached.
inline constexpr double kRandomWalkTimeRecords = 1000.0;
/// ... and when the record's length is unknown: 1e7 s (about 116 days).
inline constexpr double kRandomWalkFallbackTime = 1.0e7;

/// Fills r.columns' written figures into r.kinds, the header and the warnings (export_noise.cc).
void plan_export(const std::vector<ExportColumn>& columns, const ExportOptions& options, const std::string& source,
                 ExportResult& r);

std::string render_kalibr(const ExportOptions& o, const ExportResult& r);
std::string render_openvins(const ExportOptions& o, const ExportResult& r);
std::string render_vins(const ExportOptions& o, const ExportResult& r);
std::string render_orbslam3(const ExportOptions& o, const ExportResult& r);
/// Basalt: the calib.json fields; `sidecar` receives the header text (JSON has no comments).
std::string render_basalt(const ExportOptions& o, const ExportResult& r, std::string& sidecar);
std::string render_gz_sdf(const ExportOptions& o, const ExportResult& r);
std::string render_rotors(const ExportOptions& o, const ExportResult& r);

}  // namespace gmwm::io::export_detail
