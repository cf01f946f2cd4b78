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
#include <span>
#include <variant>
#include <vector>

#include "gmwm/io/export.h"
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
  /// The filters' labels, in order (missing ones: the source's text); at most one each.
  std::vector<std::string> labels;
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

/// The IMU model of fitted columns (a fit/select result's, or an export's): each kind's
/// columns per axis (their names' x, y, z), or its one column on the three axes; `who`
/// names the source in messages. Throws InputError when a kind is missing or an axis is
/// ambiguous.
NavModelInfo imu_model_of(const std::vector<io::ExportColumn>& columns, const std::string& who);

/// The WN + RW projection of a model, axis by axis: N and K of each axis' model read off
/// its Allan deviation (IEEE 952), as the WN + RW export formats write them.
nav::ImuModel wn_rw_projection(const nav::ImuModel& model, const std::string& label);

/// The setting a WN + RW filter runs in, for `export --consistent-for RATE,HORIZON`: aiding
/// (a position fix of `fix_sigma` per axis) at `update_rate` Hz, and once a stretch of
/// `horizon` seconds on the IMU alone (a camera dropout, a window's span): the run is
/// aided [0, H), on the IMU alone [H, 2H), aided again [2H, 3H).
struct ConsistencyOptions {
  double update_rate = 20.0;  ///< Hz
  double horizon = 60.0;      ///< s
  double fix_sigma = 0.05;    ///< m: a visual or GNSS-RTK update's error per axis
  /// The search stops when the factor is known to this relative precision.
  double precision = 0.01;
  nav::Progress progress;
  std::string Validate() const;
};

/// What a user gives for ConsistencyOptions, in every face's words after its own syntax
/// (`--consistent-for RATE,HORIZON[,SIGMA]`, Python's `consistent_for=(rate, horizon[, sigma])`).
inline constexpr const char* kConsistencyExpected =
    "the filter's update rate in Hz, the longest time on the IMU alone in s, and optionally an update's error in m "
    "(default 0.05), all positive";

/// The setting from the numbers a user gives: the update rate, the horizon and optionally the
/// update's error, all positive and finite. Empty when they are not (two or three of them):
/// the face refuses them with kConsistencyExpected.
std::optional<ConsistencyOptions> consistency_from(std::span<const double> values);

/// The smallest inflation of a WN + RW filter model that keeps it from being optimistic
/// against the truth: the expected NEES above its 95% band (nav::kNeesRuns-run mean) at no
/// more than 5% of the judged output times. First the random walks K alone (N as fitted:
/// what a WN + RW filter lacks is the bias's dynamics, a Gauss-Markov or flicker term, not
/// its white noise); when that leaves the filter inconsistent (NEES below the band: too
/// cautious somewhere), N and K together. Each by bisection on log x (the NEES falls as x
/// grows): `factor` holds and `factor / (1 + precision)` does not.
struct ConsistentInflation {
  double white = 1.0;                                ///< the factor on N
  double factor = 1.0;                               ///< the factor found: on K alone when white == 1, else on both
  nav::Verdict verdict = nav::Verdict::kConsistent;  ///< at `factor`
  double nees_inside = 0.0;                          ///< share in band at `factor`
  double smaller = 0.0;                              ///< factor / (1 + precision) (0 when factor is 1)
  double smaller_above = 0.0;                        ///< its share of output times above the band
  nav::Verdict smaller_verdict = nav::Verdict::kOptimistic;  ///< its verdict (optimistic unless factor is 1)
  std::string reason;                                        ///< one line for the file's header
};

/// Throws InputError for invalid options or models, or when no factor up to 1000 keeps
/// the filter from being optimistic.
ConsistentInflation consistent_inflation(const nav::ImuModel& truth, const nav::ImuModel& filter,
                                         const ConsistencyOptions& options);

}  // namespace gmwm::pipeline
