#pragma once
// The navigation study (docs/nav.md): what a truth noise model costs a navigation filter
// that assumes another model, for each filter model given. What `gmwm nav` and Python's
// gmwm.nav both run; they differ only in how they write the result.
//
//   gmwm::pipeline::NavStudyOptions o;
//   o.truth = gmwm::pipeline::parse_nav_source("select.json");        // a fit/select result
//   o.filters = {parse_nav_source("truth"), parse_nav_source("wnrw"),   // the truth's WN + RW
//                parse_nav_source("kalibr.yaml*3")};                  // a file, inflated x3
//   o.scenario.outages = {{300.0, 360.0}};
//   const gmwm::pipeline::NavStudy s = gmwm::pipeline::study_nav(o);
//   // s.exact.filters[k].position_rms, .verdict; s.filters[k].source
//
// A model source, as text (parse_nav_source):
//   truth                  the truth's own model (the filter that knows it)
//   wnrw                   the truth's white noise and random walk alone, per axis: N and K
//                          read off the truth's Allan deviation (what `gmwm export` writes
//                          for the WN + RW formats: Kalibr, OpenVINS, VINS, ORB-SLAM3, Basalt)
//   PATH                   a file: .json a `gmwm fit`/`gmwm select` result (each column's
//                          model, per axis), .yaml/.yml a Kalibr imu.yaml (when it has
//                          accelerometer_noise_density) or a datasheet yaml, .sdf/.xml/.urdf/
//                          .world a gz-sensors or RotorS configuration
//   gyro=SPEC;accel=SPEC   models with values, at NavStudyOptions::rate, in its units
//   any of them then *X    every noise figure times X (variances X^2): "wnrw*5"
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "gmwm/io/units.h"
#include "gmwm/nav/navigation.h"

namespace gmwm::pipeline {

struct TruthModel {};
struct WnRwProjection {};
struct ModelFile {
  std::string path;
};
struct ModelStrings {
  std::string gyro, accel;
};

struct NavSource {
  std::variant<TruthModel, WnRwProjection, ModelFile, ModelStrings> what;
  double inflate = 1.0;  ///< on every noise figure (variances inflate^2)
  std::string text;      ///< as given: the filter's label
};

/// The source a text names (grammar above). Throws InputError naming the text for an
/// empty text, a bad inflation ("*0", "*x"), or a model-string part that is not
/// gyro=... or accel=....
NavSource parse_nav_source(const std::string& text);

struct NavStudyOptions {
  nav::Scenario scenario;
  NavSource truth;
  /// Empty: the truth and its WN + RW projection.
  std::vector<NavSource> filters;
  /// Hz at which model strings' and configuration files' values are given (default: the
  /// truth's rate when it comes from a result; required otherwise).
  std::optional<double> rate;
  /// Units of model strings, and of a result's columns that do not say theirs (SI where
  /// absent).
  std::map<io::SensorKind, io::Unit> units;
  /// Monte-Carlo runs as the analysis' check (0: none); seeded, any thread count.
  int monte_carlo_runs = 0;
  std::uint64_t seed = 0;
  nav::Progress progress;
  /// "" when usable, else one line naming the field.
  std::string Validate() const;
};

/// One model as the study used it.
struct NavModelInfo {
  nav::ImuModel model;
  std::string source;              ///< where it came from, one line
  std::vector<std::string> lines;  ///< per sensor and axis: the model in SI, one line each
};

struct NavStudy {
  nav::Scenario scenario;
  NavModelInfo truth;
  std::vector<NavModelInfo> filters;
  nav::Analysis exact;
  std::optional<nav::Analysis> sampled;  ///< the Monte Carlo, when asked for
  int monte_carlo_runs = 0;
  std::uint64_t seed = 0;
  double seconds_exact = 0.0, seconds_sampled = 0.0;
};

/// Reads the models, runs the covariance analysis (and the Monte Carlo). Throws InputError
/// (one line naming the file, field or source) for anything a user gave wrong.
NavStudy study_nav(const NavStudyOptions& options);

/// The model a source gives, with `truth` (already read) for "truth" and "wnrw". Exposed
/// for `export --consistent-for` and tests.
NavModelInfo read_nav_model(const NavSource& source, const NavStudyOptions& options, const NavModelInfo* truth);

/// The WN + RW projection of a model, axis by axis: N and K of each axis' model read off
/// its Allan deviation (IEEE 952), as the WN + RW export formats write them.
nav::ImuModel wn_rw_projection(const nav::ImuModel& model, const std::string& label);

}  // namespace gmwm::pipeline
