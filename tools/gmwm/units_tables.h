#pragma once
// The CLI's --units KIND=UNIT,... (each column's unit) and --kf-rate HZ (the Kalman
// table's filter rate, the data's by default), shared by the commands; the tables
// themselves are rendered by report/study_text.h.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

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

/// Every column's unit from --units (column_unit), in the set's order.
std::vector<std::string> column_units(const UnitsOptions& o, const io::SignalSet& set);

}  // namespace gmwm::cli
