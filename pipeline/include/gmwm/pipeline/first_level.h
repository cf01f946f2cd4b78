#pragma once
// The first level a fit takes (issue 47, item 2): the finer levels of a column whose samples
// are held or interpolated are biased (repeated_samples.h) and can be left out of the fit,
// shown, not fitted. One rule for every face: `--first-level L|auto` (fit, select), Python's
// first_level=, the web app's "first_level".

#include <optional>
#include <string>

namespace gmwm::pipeline {

/// A study's first_level "auto": each column's first_fit_level (repeated_samples.h), 1
/// where its samples do not repeat.
inline constexpr int kAutoFirstLevel = 0;
/// The largest first level a face takes (tau = 2^62 samples, beyond any record).
inline constexpr int kMaxFirstLevel = 62;
/// What parse_first_level takes, for a face's refusal.
inline constexpr const char* kFirstLevelExpected = "auto or a whole number from 1 to 62";

/// "auto" (kAutoFirstLevel) or a whole number 1..kMaxFirstLevel as a first level; nullopt
/// for anything else.
std::optional<int> parse_first_level(const std::string& text);

/// Empty when `first_level` is kAutoFirstLevel or 1..kMaxFirstLevel, else what is wrong.
std::string first_level_problem(int first_level);

}  // namespace gmwm::pipeline
