// The studies' first fitted level per column (issue 47, item 2).
#include "first_level.h"

#include <algorithm>
#include <cmath>

#include "gmwm/engine/error.h"
#include "gmwm/engine/fit.h"
#include "gmwm/engine/number_text.h"
#include "gmwm/engine/repeated_samples.h"
#include "gmwm/pipeline/first_level.h"

namespace gmwm::pipeline {
namespace detail {
namespace {

// A scale as a reader sees it: "32 samples = 0.08 s".
std::string scale_text(int level, const io::SignalSet& set) {
  const double tau = std::ldexp(1.0, level);
  return significant(tau, 6) + " samples" + (set.freq_known ? " = " + significant(tau / set.freq, 3) + " s" : "");
}

}  // namespace

FittedLevels fitted_level(const io::SignalSet& set, std::size_t k, const WaveletVariance& wv, const Model& model,
                          int option, LevelUse use) {
  const std::string done = use == LevelUse::kFitted ? "fitted" : "compared";
  const io::Signal& s = set.signals[k];
  const bool automatic = option == kAutoFirstLevel;
  const int level = automatic ? first_fit_level(s.repeated, wv) : option;
  if (level == 1) return {1, {}};
  const int last = first_level(wv) + wv.levels() - 1;
  const std::string asked =
      automatic ? "first level auto (" + std::to_string(level) + ")" : "first level " + std::to_string(level);
  if (level > last || last - level + 1 < model.num_parameters())
    throw InputError(s.name + ": " + asked + " leaves " + std::to_string(std::max(last - level + 1, 0)) +
                     " of the WV's levels 1.." + std::to_string(last) + ", fewer than the model's " +
                     std::to_string(model.num_parameters()) + " parameters: a lower first level or a smaller model");
  const std::string from = done + " from level " + std::to_string(level) + " (tau = " + scale_text(level, set) + ")";
  const std::string finer = level > 2 ? "levels 1-" + std::to_string(level - 1) : std::string("level 1");
  return {level, automatic ? from + ": " + finer + ", biased by " + (s.repeated.held() ? "held" : "interpolated") +
                                 " samples beyond a quarter of their standard error, shown, not " + done
                           : from + " as asked: " + finer + " shown, not " + done};
}

std::vector<FittedLevels> fitted_levels(const io::SignalSet& set, const std::vector<WaveletVariance>& wvs,
                                        const Model& model, int option) {
  std::vector<FittedLevels> out;
  for (std::size_t k = 0; k < wvs.size(); ++k)
    out.push_back(fitted_level(set, k, wvs[k], model, option, LevelUse::kFitted));
  return out;
}

std::vector<WaveletVariance> fitted_wvs(const std::vector<WaveletVariance>& wvs,
                                        const std::vector<FittedLevels>& levels) {
  std::vector<WaveletVariance> out;
  for (std::size_t k = 0; k < wvs.size(); ++k)
    out.push_back(levels[k].first == 1 ? wvs[k] : drop_fine_levels(wvs[k], levels[k].first));
  return out;
}

void restore_levels(FitResult& fit, const WaveletVariance& wv, const FittedLevels& levels) {
  if (levels.first == 1) return;
  fit.notes.insert(fit.notes.begin(), levels.reason);
  if (fit.status != FitStatus::kFailed && fit.theta.size() == fit.model.num_parameters())
    fit.implied_wv = fit.model.wv(fit.theta, wv.tau);
}

}  // namespace detail

std::optional<int> parse_first_level(const std::string& text) {
  if (text == "auto") return kAutoFirstLevel;
  if (text.empty() || text.size() > 2 || text.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
  const int v = std::stoi(text);
  if (v < 1 || v > kMaxFirstLevel) return std::nullopt;
  return v;
}

std::string first_level_problem(int first_level) {
  if (first_level == kAutoFirstLevel || (first_level >= 1 && first_level <= kMaxFirstLevel)) return {};
  return "first level: found " + std::to_string(first_level) + ", expected " + kFirstLevelExpected;
}

}  // namespace gmwm::pipeline
