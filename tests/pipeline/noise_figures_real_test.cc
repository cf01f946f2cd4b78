// Issue 43 acceptance: on every shipped ADIS16405 unit (three units x 6 axes, 100 Hz, gyro
// deg/s, accel g; $GMWM_SHARED_DATA), the N and B that select, fit and wv write agree with an
// Allan read-off written here, independently of gmwm's own (its Allan deviation and its
// read-off functions are not used):
//
//   The curve: the plain overlapping Allan deviation (IEEE Std 1139; W. J. Riley, Handbook of
//   Frequency Stability Analysis, NIST SP 1065, eq. 14) of the column's samples at the
//   half-octave averaging factors m = 1, 2, 3, 4, 6, 8, 12, ... (2^k and 3 2^(k-1)), kept
//   while the record holds at least ten averaging times (m <= n / 10).
//   N (white floor): the straight -1/2 stretches of the curve are the runs of consecutive
//   segments (point to point) whose log-log slope is within 0.1 of -1/2; N is the median of
//   ADEV(tau) sqrt(tau) over the points of the longest run (the finer on a tie).
//   B: the lowest local minimum of the curve (a point below both its neighbours: a curve
//   still falling at its last point has not shown its floor there) divided by
//   sqrt(2 ln 2 / pi) = 0.664 (IEEE Std 952, Annex C).
//
// Bars (the issue's): N within 15%, B within 25%. The same rule is in docs/noise-figures.md
// ("How the figures are checked").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

#include "gmwm/engine/noise_figures.h"
#include "gmwm/io/signal_reader.h"
#include "gmwm/pipeline/fit_study.h"
#include "gmwm/pipeline/select_study.h"
#include "gmwm/pipeline/wv_study.h"
#include "test_support.h"

namespace gmwm::pipeline {
namespace {

// The acceptance bars.
constexpr double kWhiteBar = 0.15;
constexpr double kInstabilityBar = 0.25;
// sqrt(2 ln 2 / pi): a flicker floor's Allan deviation per unit B (IEEE Std 952, Annex C).
const double kFlickerFloorPerB = std::sqrt(2.0 * std::log(2.0) / std::acos(-1.0));

struct Curve {
  std::vector<double> tau, adev;
};

// The overlapping Allan deviation from the prefix sums of the mean-centred series.
Curve overlapping_adev(std::span<const double> x, double freq) {
  const auto n = static_cast<std::int64_t>(x.size());
  double mean = 0.0;
  for (double v : x) mean += v;
  mean /= static_cast<double>(n);
  std::vector<double> s(static_cast<std::size_t>(n) + 1, 0.0);
  for (std::int64_t t = 0; t < n; ++t)
    s[static_cast<std::size_t>(t) + 1] = s[static_cast<std::size_t>(t)] + (x[static_cast<std::size_t>(t)] - mean);
  Curve c;
  for (std::int64_t m = 1; 10 * m <= n;) {
    double sum = 0.0;
    for (std::int64_t t = 0; t + 2 * m <= n; ++t) {
      const auto i = static_cast<std::size_t>(t), um = static_cast<std::size_t>(m);
      const double d = s[i + 2 * um] - 2.0 * s[i + um] + s[i];
      sum += d * d;
    }
    const auto md = static_cast<double>(m);
    c.tau.push_back(md / freq);
    c.adev.push_back(std::sqrt(sum / (2.0 * md * md * static_cast<double>(n - 2 * m + 1))));
    // Half octaves: 1, 2, 3, 4, 6, 8, 12, ...
    const bool power_of_two = (m & (m - 1)) == 0;
    m = power_of_two && m >= 2 ? m / 2 * 3 : power_of_two ? 2 : m / 3 * 4;
  }
  return c;
}

double white_floor(const Curve& c) {
  std::size_t best_first = 0, best_count = 0;
  for (std::size_t i = 0; i + 1 < c.tau.size();) {
    std::size_t j = i;
    while (j + 1 < c.tau.size() &&
           std::abs(std::log(c.adev[j + 1] / c.adev[j]) / std::log(c.tau[j + 1] / c.tau[j]) + 0.5) <= 0.1)
      ++j;
    if (j - i > best_count) best_first = i, best_count = j - i;
    i = j + 1;
  }
  if (best_count == 0) return NAN;
  std::vector<double> line;
  for (std::size_t k = best_first; k <= best_first + best_count; ++k) line.push_back(c.adev[k] * std::sqrt(c.tau[k]));
  std::sort(line.begin(), line.end());
  const std::size_t h = line.size() / 2;
  return line.size() % 2 ? line[h] : 0.5 * (line[h - 1] + line[h]);
}

double instability(const Curve& c) {
  double lowest = NAN;
  for (std::size_t i = 1; i + 1 < c.adev.size(); ++i)
    if (c.adev[i] < c.adev[i - 1] && c.adev[i] < c.adev[i + 1] && !(c.adev[i] >= lowest)) lowest = c.adev[i];
  return lowest / kFlickerFloorPerB;
}

struct Reference {
  double white = NAN, instability = NAN;
};

// One line per face and axis, so that a failure shows the whole table.
void expect_near_reference(const std::string& face, const std::string& unit, const std::string& column,
                           const ChosenFigures& f, const Reference& ref) {
  const double rn = f.white.figure.value / ref.white, rb = f.instability.figure.value / ref.instability;
  std::printf("%-8s %s %-8s N %.4g / %.4g = %.3f (%s)   B %.4g / %.4g = %.3f (%s)\n", face.c_str(), unit.c_str(),
              column.c_str(), f.white.figure.value, ref.white, rn, to_string(f.white.source),
              f.instability.figure.value, ref.instability, rb, to_string(f.instability.source));
  EXPECT_NEAR(rn, 1.0, kWhiteBar) << face << " " << unit << " " << column << ": " << f.white.note;
  EXPECT_NEAR(rb, 1.0, kInstabilityBar) << face << " " << unit << " " << column << ": " << f.instability.note;
}

TEST(NoiseFiguresOnTheShippedAdisUnits, AgreeWithAnIndependentAllanReadOffOnAll18Axes) {
  GMWM_REQUIRE_SHARED_DATA();
  for (const char* unit : {"adis_16405_imu1.csv.gz", "adis_16405_imu2.csv.gz", "adis_16405_imu3.csv.gz"}) {
    io::ReadOptions ro;
    ro.freq = 100.0;
    const io::SignalSet set = io::read_signals(test::shared_data_file(unit), ro);
    ASSERT_EQ(set.signals.size(), 6u) << unit;
    std::vector<Reference> refs;
    for (const auto& s : set.signals) {
      const Curve c = overlapping_adev(s.values, set.freq);
      refs.push_back({white_floor(c), instability(c)});
    }
    // wv --adev: the data's own figures.
    WvStudyOptions wo;
    wo.allan = AllanOptions{};
    const WvStudy wv = study_wv(set, wo);
    // select over the maximal model the issue used, and fit of the three-term model.
    SelectStudyOptions so;
    so.models = {ModelSpec("3*AR1+WN+RW+QN+DR")};
    const SelectStudy sel = study_select(set, so);
    FitStudyOptions fo;
    fo.model = ModelSpec("AR1+WN+RW");
    const FitStudy fit = study_fit(set, fo);
    for (std::size_t k = 0; k < set.signals.size(); ++k) {
      const std::string& name = set.signals[k].name;
      ASSERT_TRUE(wv.columns[k].allan && sel.columns[k].figures && fit.columns[k].figures) << unit << " " << name;
      expect_near_reference("wv", unit, name, wv.columns[k].allan->chosen, refs[k]);
      expect_near_reference("select", unit, name, sel.columns[k].figures->chosen, refs[k]);
      expect_near_reference("fit", unit, name, fit.columns[k].figures->chosen, refs[k]);
    }
  }
}

}  // namespace
}  // namespace gmwm::pipeline
