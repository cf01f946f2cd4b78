#pragma once
// Internals of the frequency-stability study's outputs (stability_output.h), shared by the
// terminal's tables (stability_output.cc, which defines them) and the HTML report
// (stability_page.cc): the units and the three-cornered hat's words, said once.

#include <cstddef>
#include <string>
#include <vector>

#include "gmwm/pipeline/stability_study.h"

namespace gmwm::report::detail {

/// A deviation's unit: the data's, the time deviations' the data's times seconds
/// ("(deg/s)*s"); "" when the data's is.
std::string deviation_unit(stability::DeviationKind kind, const std::string& data_unit);

/// The hat's data unit: the three columns' when they share one, else "" (unknown).
std::string hat_unit(const std::vector<std::string>& units);

/// "three-cornered hat of A, B, C: each column's own deviation, separated from what the three
/// share" (the names as given: escape them for HTML).
std::string hat_heading(const pipeline::StabilityHat& hat);

/// A sensor's separated deviation at factor i as the tables write it: the value, or "[var V]"
/// where its separated variance V is negative (no deviation).
std::string hat_value_text(const stability::HatSensor& s, std::size_t i);

/// Whether any sensor of any kind of the hat has a negative separated variance.
bool hat_has_negative(const pipeline::StabilityHat& hat);

/// What "[var V]" says: the variance is negative, no deviation, kept as computed.
std::string hat_negative_note();

/// How the hat's intervals are formed: "the P% score interval of each separated variance from
/// edf, the smallest of the three pairs' degrees of freedom".
std::string hat_interval_words(double confidence);

}  // namespace gmwm::report::detail
