#pragma once
// The CLI's continuous-units and Kalman-filter tables (issue 6, items 2 and 4), shared by
// `fit` and `select`: --units KIND=UNIT,... names each column's unit; --kf-rate HZ the
// filter's rate (the data's by default).
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "gmwm/engine/fit.h"
#include "gmwm/engine/noise_figures.h"
#include "gmwm/report/json_output.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/io/units.h"

namespace gmwm::cli {

struct UnitsOptions {
  std::string units;     ///< --units gyro=deg/s,accel=g
  double kf_rate = 0.0;  ///< --kf-rate HZ; 0: the data's rate
};

/// Adds --units and --kf-rate.
void add_units_options(CLI::App& sub, UnitsOptions& o);
/// Adds --units alone (commands without a Kalman table).
void add_units_option(CLI::App& sub, UnitsOptions& o);

/// The column's unit name from --units (io::unit_of_column), "" when --units was not given.
/// Throws InputError for a bad --units.
std::string column_unit(const UnitsOptions& o, const std::string& column);

/// The filter rate: --kf-rate, else the data's rate (0 when unknown).
double filter_rate(const UnitsOptions& o, const io::SignalSet& set);

/// The column's info with its unit, for report::continuous_json / kalman_json.
report::ColumnInfo with_unit(report::ColumnInfo info, const UnitsOptions& o);

/// Text tables: the parameters in continuous units with their intervals, and the Kalman
/// filter terms (empty strings when the rate is unknown or the fit unusable).
std::string continuous_table(const FitResult& fit, const report::ColumnInfo& column);
std::string kalman_table(const FitResult& fit, const report::ColumnInfo& column, double filter_rate,
                         const ChosenFigures* figures = nullptr);

/// The noise figures N, K, B (IEEE 952 read-offs): the value to use with its source,
/// interval and where it was read, the model's and the data's read-offs side by side,
/// the components behind each, and a note where the model misses the data.
std::string noise_figures_table(const ChosenFigures& figures, const std::string& unit);

}  // namespace gmwm::cli
