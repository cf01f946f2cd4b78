#pragma once
// gmwm fit --curve FILE --model SPEC [--value adev|avar|wv] [--exclude-taus RANGES]
//          [--record SECONDS] [--curve-confidence C] [--freq HZ] [--columns a,b] ...
// The fit of a model to a given Allan-deviation, Allan-variance or wavelet-variance curve
// instead of a record (pipeline/curve_study.h, docs/curve-fit.md): `gmwm fit`'s options
// that read a record are refused beside it.
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "common.h"
#include "units_tables.h"

namespace gmwm::cli {

/// The options of a curve fit.
struct CurveArgs {
  std::string curve;             ///< --curve FILE; empty: fit reads INPUT
  std::string value;             ///< --value adev|avar|wv; empty: from the value column's name
  std::string exclude_taus;      ///< --exclude-taus RANGES (pipeline::parse_tau_ranges)
  std::optional<double> record;  ///< --record SECONDS
  double confidence = 0.95;      ///< --curve-confidence C: the given intervals' level
};

/// What the curve fit takes of `gmwm fit`'s own options.
struct CurveFitSettings {
  std::string model, omega;
  double alpha = 0.05;
  int max_evaluations = 0;
  std::optional<double> freq;          ///< --freq: the rate of the data behind the curve
  std::optional<std::string> columns;  ///< --columns: the curves to fit
  UnitsOptions units;
};

/// Adds --curve, --value, --exclude-taus, --record and --curve-confidence to `fit`.
void add_curve_options(CLI::App& sub, CurveArgs& args);

/// Runs the curve fit; `sub` is `fit`'s node, whose options that read a record (INPUT,
/// --topic, --levels, --robust, --joint, --first-level, ...) are refused beside --curve, as
/// is --report (InputError, exit 2). Returns the exit code (1 when every fit failed).
int run_curve_fit(const CLI::App& sub, const CurveArgs& args, const CurveFitSettings& settings,
                  const CommonOptions& common);

}  // namespace gmwm::cli
