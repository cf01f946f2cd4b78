#include "units_tables.h"

#include "common.h"

#include "gmwm/engine/error.h"

namespace gmwm::cli {

void add_units_option(CLI::App& sub, UnitsOptions& o) {
  sub.add_option("--units", o.units,
                 "Units of the columns, e.g. gyro=deg/s,accel=g: continuous quantities are then given in them")
      ->type_name("KIND=UNIT,...");
}

void add_units_options(CLI::App& sub, UnitsOptions& o) {
  add_units_option(sub, o);
  sub.add_option_function<double>(
         "--kf-rate",
         [&o](const double& f) {
           if (const std::string why = io::sampling_rate_problem(f, "--kf-rate"); !why.empty())
             throw CLI::ValidationError(why);
           o.kf_rate = f;
         },
         "Rate of the Kalman filter for the Q/R table (default: the data's rate)")
      ->type_name("HZ")
      ->transform(decimal_number("a sampling rate in Hz"));
}

std::string column_unit(const UnitsOptions& o, const std::string& column) {
  return io::unit_of_column(io::parse_units_spec(o.units), column);
}

double filter_rate(const UnitsOptions& o, const io::SignalSet& set) {
  if (o.kf_rate > 0.0) return o.kf_rate;
  return set.freq_known ? set.freq : 0.0;
}

std::vector<std::string> column_units(const UnitsOptions& o, const io::SignalSet& set) {
  std::vector<std::string> units;
  for (const auto& s : set.signals) units.push_back(column_unit(o, s.name));
  return units;
}

}  // namespace gmwm::cli
