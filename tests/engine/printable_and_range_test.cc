// What reaches a terminal or a message (error.h) and when a wavelet variance can be used
// (wavelet_variance.h: wv_range_problem).
#include <gtest/gtest.h>

#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "gmwm/engine/classical_wv.h"
#include "gmwm/engine/error.h"
#include "gmwm/engine/wavelet_variance.h"

namespace gmwm {
namespace {

TEST(PrintableText, KeepsLineBreaksTabsAndUtf8AndShowsEveryOtherControlAsHex) {
  EXPECT_EQ(printable_text("a\tb\nc \xC3\xA9\n"), "a\tb\nc \xC3\xA9\n");
  EXPECT_EQ(printable_text("x\x1b[2Jy"), "x\\x1B[2Jy");
  EXPECT_EQ(printable_text("over\rwrite"), "over\\x0Dwrite");
  EXPECT_EQ(printable_text("bell\x07"), "bell\\x07");
  EXPECT_EQ(printable_text("del\x7f"), "del\\x7F");
  // C1 controls are valid UTF-8 but act as escapes (U+009B is CSI): shown as bytes.
  EXPECT_EQ(printable_text("c1\xC2\x9B"
                           "31m"),
            "c1\\xC2\\x9B31m");
  EXPECT_EQ(printable_text("nbsp\xC2\xA0ok"), "nbsp\xC2\xA0ok");
  EXPECT_EQ(printable_text(std::string("nul\0x", 5)), "nul\\x00x");
  EXPECT_EQ(printable_text("bad\xFF"), "bad\\xFF");
}

TEST(PrintableLine, IsOneLineWithTheSameEscapes) {
  EXPECT_EQ(printable_line("a\nb\r\nc\x1b "), "a b  c\\x1B");
  EXPECT_EQ(printable_line("\xC2\x85next line"), "\\xC2\\x85next line");
}

std::vector<double> series(double scale, std::size_t n = 4096) {
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i)
    x[i] = scale * (std::sin(0.37 * static_cast<double>(i)) + 0.1 * static_cast<double>(i % 7));
  return x;
}

WaveletVariance wv_of(const std::vector<double>& x) {
  return classical_wv(std::vector<std::span<const double>>{std::span<const double>(x)}, WvOptions{}).front();
}

TEST(WvRangeProblem, AcceptsOrdinaryDataAndNamesConstantUnderflowingAndOverflowingOnes) {
  for (double scale : {1e-12, 1.0, 1e12}) {
    const auto x = series(scale);
    EXPECT_EQ(wv_range_problem(wv_of(x), x, true), "") << scale;
  }
  const std::vector<double> constant(1000, 2.5);
  EXPECT_NE(wv_range_problem(wv_of(constant), constant, false).find("found all 1000 values equal to 2.5"),
            std::string::npos);
  const auto tiny = series(1e-300);
  EXPECT_NE(wv_range_problem(wv_of(tiny), tiny, false).find("zero at every level although the values vary"),
            std::string::npos);
  const auto huge = series(1e160);
  EXPECT_NE(wv_range_problem(wv_of(huge), huge, false).find("is not a finite number"), std::string::npos);
}

TEST(WvRangeProblem, AFitNeedsLevelsWithinTheRangeItsParametersReach) {
  // Levels near 1e-40: representable (a WV alone is fine), too small for a fit whose
  // variances are exp(u), |u| <= 100 (3.7e-44).
  const auto x = series(1e-20);
  const WaveletVariance wv = wv_of(x);
  EXPECT_EQ(wv_range_problem(wv, x, false), "");
  const std::string why = wv_range_problem(wv, x, true);
  EXPECT_NE(why.find("outside 1e-30 .. 1e+30, the range a fit can take"), std::string::npos) << why;
  EXPECT_NE(why.find("rescale"), std::string::npos) << why;
  EXPECT_LT(kMinFittableWv, kMaxFittableWv);
  EXPECT_GT(kMinFittableWv, std::exp(-100.0) * 1e13) << "13 orders of magnitude below the total for small components";
}

}  // namespace
}  // namespace gmwm
