// io::option_wording: one table of the CLI's options and the fields that set them, read by
// every face (issue 45).
#include "gmwm/io/option_wording.h"

#include <gtest/gtest.h>

namespace gmwm::io {
namespace {

TEST(OptionWording, GivesTheCommandLineItsOwnMessageUnchanged) {
  const std::string m = "data.csv: no timestamp column found; give the sampling rate with --freq HZ";
  EXPECT_EQ(option_wording(m, Face::kCli), m);
}

TEST(OptionWording, NamesTheWebRequestsFieldsWhereTheLibrarySaysAnOption) {
  EXPECT_EQ(option_wording("data.csv: no timestamp column found; give the sampling rate with --freq HZ", Face::kWeb),
            "data.csv: no timestamp column found; give the sampling rate with \"freq\" (Hz)");
  EXPECT_EQ(option_wording("the units do not fit; give --units gyro=deg/s, or --no-unit-check", Face::kWeb),
            "the units do not fit; give \"units\" gyro=deg/s, or \"unit_check\": false");
  EXPECT_EQ(option_wording("no accelerometer column (--partial leaves it out)", Face::kWeb),
            "no accelerometer column (\"partial\": true leaves it out)");
}

TEST(OptionWording, NamesPythonsKeywordArgumentsWhereTheLibrarySaysAnOption) {
  EXPECT_EQ(option_wording("--units 'furlong': expected one unit (rad/s, deg/s)", Face::kPython),
            "units 'furlong': expected one unit (rad/s, deg/s)");
  EXPECT_EQ(
      option_wording("give the rate with --freq HZ, or --no-unit-check; --partial to leave it out", Face::kPython),
      "give the rate with freq (Hz), or unit_check=False; partial=True to leave it out");
  EXPECT_EQ(option_wording("--consistent-for: needs both sensors; leave out --inflate", Face::kPython),
            "consistent_for: needs both sensors; leave out inflate");
  EXPECT_EQ(option_wording("--temperature 'T': no such column; --replicates: at least 2", Face::kPython),
            "temperature 'T': no such column; replicates: at least 2");
}

TEST(OptionWording, NamesTheStabilityKeywordsWhereTheLibrarySaysTheirOptions) {
  EXPECT_EQ(option_wording("--kind: found 'allan', expected adev, oadev", Face::kPython),
            "kind: found 'allan', expected adev, oadev");
  EXPECT_EQ(option_wording("--taus: 2.5 s is not a whole number; --confidence: found 1.5", Face::kPython),
            "taus: 2.5 s is not a whole number; confidence: found 1.5");
  EXPECT_EQ(option_wording("--intervals: found 'fast'; --noise-alpha: found -5", Face::kPython),
            "intervals: found 'fast'; noise_alpha: found -5");
  EXPECT_EQ(option_wording("--hat: the three-cornered hat reads three columns", Face::kPython),
            "hat=True: the three-cornered hat reads three columns");
  EXPECT_EQ(option_wording("--hat: mtie is a maximum", Face::kWeb), "\"hat\": true: mtie is a maximum");
  // --curve-confidence is fit_curve's confidence, not a longer --confidence.
  EXPECT_EQ(option_wording("--curve-confidence: found 2", Face::kPython), "confidence: found 2");
}

TEST(OptionWording, ReplacesWholeOptionsOnly) {
  // An option that starts a longer one, or ends one, is not that option.
  EXPECT_EQ(option_wording("--frequency and --freqs and x--units-file", Face::kPython),
            "--frequency and --freqs and x--units-file");
  EXPECT_EQ(option_wording("--freq=100 or (--freq)", Face::kPython), "freq=100 or (freq)");
  EXPECT_EQ(option_wording("--units --units", Face::kWeb), "\"units\" \"units\"");
}

TEST(OptionWording, LeavesAMessageWithoutOptionsAsItIs) {
  EXPECT_EQ(option_wording("", Face::kPython), "");
  EXPECT_EQ(option_wording("alpha must be in (0, 1), got 2", Face::kWeb), "alpha must be in (0, 1), got 2");
}

}  // namespace
}  // namespace gmwm::io
