// A fleet's rows against its spec mask (fleet_study.h, check_spec): each figure converted to
// the limit's own unit, compared, and what its interval says.
#include <cmath>
#include <cstdio>
#include <string>

#include "gmwm/engine/noise_figures.h"
#include "gmwm/fleet/fleet_study.h"
#include "gmwm/io/units.h"
#include "gmwm/engine/number_text.h"

namespace gmwm::fleet {
namespace {

std::string g(double x) { return significant(x, 3); }

// The row's sensor kind and its unit per SI unit: from the declared unit, else from the
// column's name with SI assumed. nullopt when neither tells the kind.
struct RowUnit {
  io::SensorKind kind;
  double per_si = 1.0;
  bool assumed_si = false;
};
std::optional<RowUnit> row_unit(const FleetRow& r) {
  if (!r.data_unit.empty()) {
    try {
      const auto [kind, unit] = io::parse_any_unit(r.data_unit);
      return RowUnit{kind, unit.per_si, false};
    } catch (const std::exception&) {
    }
  }
  try {
    return RowUnit{io::sensor_kind_of_column(r.axis), 1.0, true};
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

SpecCheck check_figure(char name, const ChosenFigure& f, const io::SpecLimit& limit, bool as_minimum,
                       const RowUnit& u) {
  SpecCheck c;
  c.figure = name;
  c.limit = limit;
  // The figure in the limit's unit: data unit -> SI (divide by per_si) -> the limit's unit
  // (the file's number per SI unit: written value / limit.si).
  const double written_value = limit.value;
  const double to_limit = limit.si > 0.0 ? written_value / limit.si : 1.0;
  const double scale = (as_minimum ? kBiasInstabilityFactor : 1.0) / u.per_si * to_limit;
  c.value = f.figure.value * scale;
  c.low = f.figure.low * scale;
  c.high = f.figure.high * scale;
  const std::string what = std::string(1, name) + (as_minimum ? " (as the Allan minimum 0.664 B)" : "");
  const std::string& unit = limit.unit;
  const std::string versus = g(c.value) + " " + unit + " against the spec's " + limit.written;
  if (!std::isfinite(c.value)) {
    c.note = what + ": no read-off to check against the spec's " + limit.written;
    return c;
  }
  if (f.figure.status == ReadoffStatus::kBound) {
    c.verdict = c.value <= written_value ? SpecVerdict::kPass : SpecVerdict::kUnknown;
    c.note = what + ": the data bound it from above only, at " + versus +
             (c.verdict == SpecVerdict::kPass ? ": within" : ": cannot tell");
    return c;
  }
  c.verdict = c.value <= written_value ? SpecVerdict::kPass : SpecVerdict::kFail;
  std::string interval;
  if (std::isfinite(c.low) && std::isfinite(c.high)) {
    const std::string range = " (interval " + g(c.low) + "-" + g(c.high) + ")";
    if (c.verdict == SpecVerdict::kFail)
      interval = c.low > written_value ? range + ", wholly above it" : range + ", reaching below it";
    else
      interval = c.high > written_value ? range + ", reaching above it" : range + ", wholly within it";
  }
  c.note = what + " " + versus + (c.verdict == SpecVerdict::kFail ? ": above the limit" : ": within") + interval;
  return c;
}

}  // namespace

const char* to_string(SpecVerdict v) {
  switch (v) {
    case SpecVerdict::kPass:
      return "pass";
    case SpecVerdict::kFail:
      return "fail";
    case SpecVerdict::kUnknown:
      return "unknown";
  }
  return "?";
}

void check_spec(std::vector<FleetRow>& rows, const io::FleetSpec& spec) {
  for (FleetRow& r : rows) {
    r.spec.clear();
    r.spec_note.clear();
    if (r.axis.empty()) continue;  // a failed recording
    const std::optional<RowUnit> u = row_unit(r);
    if (!u) {
      r.spec_note =
          "the spec cannot be applied: neither the unit nor the column's name tells a gyroscope or an "
          "accelerometer";
      continue;
    }
    const io::SensorLimits* l = spec.limits(r.model, u->kind);
    if (!l) {
      r.spec_note = "no limits in the spec for model " + r.model + "'s " +
                    (u->kind == io::SensorKind::kGyro ? "gyroscope" : "accelerometer");
      continue;
    }
    if (!r.figures_known) {
      r.spec_note = "no noise figures (no rate or no usable fit) to check against the spec";
      continue;
    }
    if (l->white) r.spec.push_back(check_figure('N', r.figures.white, *l->white, false, *u));
    if (l->walk) r.spec.push_back(check_figure('K', r.figures.walk, *l->walk, false, *u));
    if (l->instability)
      r.spec.push_back(check_figure('B', r.figures.instability, *l->instability, l->instability_is_minimum, *u));
    if (u->assumed_si) r.spec_note = "the data's unit is not declared: taken as SI (" + io::si_unit(u->kind).name + ")";
  }
}

}  // namespace gmwm::fleet
