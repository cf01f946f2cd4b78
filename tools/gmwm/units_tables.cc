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

report::ColumnInfo with_unit(report::ColumnInfo info, const UnitsOptions& o) {
  info.unit = column_unit(o, info.name);
  return info;
}

std::string continuous_table(const FitResult& fit, const report::ColumnInfo& column) {
  const report::Json rows = report::continuous_json(fit, column);
  if (rows.empty()) return {};
  Table t({"continuous", "value", "CI low", "CI high", "unit"}, 1);
  for (const auto& r : rows) {
    if (r.at("unit").get<std::string>().empty()) continue;  // no physical counterpart (MA1, ARMA)
    auto num = [](const report::Json& v) { return v.is_number() ? fmt(v.get<double>(), 5) : std::string("-"); };
    t.add({r.at("process").get<std::string>() + " " + r.at("name").get<std::string>(), num(r.at("value")),
           num(r.at("ci_low")), num(r.at("ci_high")), r.at("unit").get<std::string>()});
  }
  return t.str();
}

std::string kalman_table(const FitResult& fit, const report::ColumnInfo& column, double filter_rate,
                         const ChosenFigures* figures) {
  const report::Json k = report::kalman_json(fit, column, filter_rate, figures);
  if (k.at("terms").empty()) return {};
  Table t({"Kalman filter at " + fmt(filter_rate, 6) + " Hz", "role", "q (continuous)", "F", "R or Q_d", "note"}, 2);
  auto num = [](const report::Json& v, const report::Json& unit) {
    if (!v.is_number()) return std::string("-");
    return fmt(v.get<double>(), 5) + (unit.is_string() ? " " + unit.get<std::string>() : "");
  };
  for (const auto& r : k.at("terms"))
    t.add({r.at("process").get<std::string>(), r.at("role").get<std::string>(), num(r.at("q"), r.at("q_unit")),
           num(r.at("transition"), nullptr), num(r.at("discrete"), r.at("discrete_unit")),
           r.at("note").get<std::string>()});
  return t.str();
}

std::string noise_figures_table(const ChosenFigures& figures, const std::string& unit) {
  const report::FigureUnits units = report::figure_units(unit);
  Table t({"noise figure (IEEE 952)", "value", "CI low", "CI high", "unit", "source", "model's", "data's", "read"}, 1);
  auto status = [](const Readoff& r) {
    if (!r.available()) return std::string("-");
    return fmt(r.value, 4) + (r.status == ReadoffStatus::kBound ? " (bound)" : "");
  };
  std::string notes;
  auto row = [&](const char* name, const ChosenFigure& c, const std::string& u) {
    const Readoff& f = c.figure;
    t.add({name, fmt(f.value, 5), fmt(f.low, 4), fmt(f.high, 4), u, to_string(c.source), status(c.model),
           status(c.data), f.how});
    std::string comps;
    for (const auto& [component, share] : c.model.sources)
      comps += (comps.empty() ? "" : ", ") + component + " " + fmt(100.0 * share, 3) + "%";
    notes += std::string("  ") + name + ": " + c.note + (comps.empty() ? "" : "; model's curve there: " + comps) + "\n";
  };
  row("N white noise", figures.white, units.white);
  row("K random walk", figures.walk, units.walk);
  row("B bias instability", figures.instability, units.instability);
  return t.str() + notes;
}

}  // namespace gmwm::cli
