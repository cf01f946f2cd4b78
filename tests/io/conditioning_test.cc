// What reading does to the values on request (issue 47, items 4 and 5; issue 48): --data
// increment reads delta-angles and delta-velocities as rates (x the rate), --data phase a
// phase or time error as the rate of its first differences, --decimate K keeps one sample
// in K after the mean of each block (or none), the rate becomes rate / K, and the set says
// what was done; bad requests are refused naming the option.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "gmwm/engine/error.h"
#include "gmwm/io/signal_reader.h"
#include "signal_test_util.h"
#include "test_support.h"

namespace {

using gmwm::io::DataKind;
using gmwm::io::DecimationFilter;

// x_k = k (a ramp) at 100 Hz, stamped in seconds, with `skip` samples left out at 50.
std::string ramp_csv(int n, int skip = 0) {
  std::string csv = "time [s],x\n";
  for (int k = 0; k < n; ++k)
    if (k < 50 || k >= 50 + skip) csv += std::to_string(k / 100.0) + "," + std::to_string(k) + "\n";
  return csv;
}

gmwm::io::SignalSet read_with(const std::string& csv, const gmwm::io::ReadOptions& o) {
  const std::string dir = gmwm::test::temp_dir("conditioning");
  const std::string path = gmwm::test::write_text(dir, "c.csv", csv);
  try {
    gmwm::io::SignalSet set = gmwm::io::read_signals(path, o);
    std::filesystem::remove_all(dir);
    return set;
  } catch (...) {
    std::filesystem::remove_all(dir);
    throw;
  }
}

TEST(Conditioning, AveragingDecimationKeepsTheMeanOfEachBlockAtTheRateOverK) {
  gmwm::io::ReadOptions o;
  o.decimate = 4;
  const gmwm::io::SignalSet set = read_with(ramp_csv(203), o);
  const gmwm::Samples& v = set.signals.front().values;
  ASSERT_EQ(v.size(), 50u);  // 203 / 4 blocks; the last 3 samples are left out
  EXPECT_DOUBLE_EQ(v[0], 1.5);
  EXPECT_DOUBLE_EQ(v[49], 197.5);
  EXPECT_NEAR(set.freq, 25.0, 1e-9);  // the stamps' rate (steps of 0.01 s written as decimals) / 4
  EXPECT_NEAR(set.freq_before_decimation, 100.0, 1e-9);
  EXPECT_EQ(gmwm::io::conditioning_summary(set),
            "decimated by 4 (the mean of each 4 samples) from 100 Hz to 25 Hz: N, K and B are those of the band "
            "below 12.5 Hz, as in the record");
}

TEST(Conditioning, DecimationWithoutAFilterKeepsEveryKthSampleAndSaysItAliases) {
  gmwm::io::ReadOptions o;
  o.decimate = 4;
  o.decimate_filter = DecimationFilter::kNone;
  const gmwm::io::SignalSet set = read_with(ramp_csv(200), o);
  EXPECT_DOUBLE_EQ(set.signals.front().values[1], 4.0);
  EXPECT_NE(gmwm::io::conditioning_summary(set).find("folds in, white noise's N grows sqrt(4) times"),
            std::string::npos);
}

TEST(Conditioning, IncrementsAreReadAsRatesTimesTheSamplingRate) {
  gmwm::io::ReadOptions o;
  o.data = DataKind::kIncrement;
  const gmwm::io::SignalSet set = read_with(ramp_csv(64), o);
  EXPECT_DOUBLE_EQ(set.signals.front().values[3], 300.0);  // 3 per period of 10 ms: 300 a second
  EXPECT_EQ(gmwm::io::conditioning_summary(set), "read as increments x 100 Hz (rates: rad -> rad/s, m/s -> m/s^2)");
}

TEST(Conditioning, PhaseIsReadAsTheRateOfItsFirstDifferencesOneSampleFewer) {
  gmwm::io::ReadOptions o;
  o.data = DataKind::kPhase;
  const gmwm::io::SignalSet set = read_with(ramp_csv(64), o);
  ASSERT_EQ(set.signals.front().values.size(), 63u);
  EXPECT_NEAR(set.signals.front().values[5], 100.0, 1e-9);  // a step of 1 per 10 ms
  EXPECT_EQ(gmwm::io::conditioning_summary(set),
            "read as phase: its first differences x 100 Hz (s -> fractional frequency, rad -> rad/s), one sample "
            "fewer");
  // A step across a gap spans several periods, missing or joined: refused either way (joining
  // would read the step as one period's frequency), and so are too few steps.
  for (const auto gaps : {gmwm::io::GapHandling::kCompleteWindows, gmwm::io::GapHandling::kJoin}) {
    o.gaps = gaps;
    try {
      read_with(ramp_csv(400, 3), o);
      FAIL() << "took phase across a gap";
    } catch (const gmwm::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("c.csv: --data phase: found 1 gaps, expected a regular record (a phase "
                                           "step across a gap spans several periods, joined or not); cut the record "
                                           "at its gaps"),
                std::string::npos)
          << e.what();
    }
  }
  o.gaps = gmwm::io::GapHandling::kCompleteWindows;
  try {
    read_with(ramp_csv(16), o);
    FAIL() << "took 15 steps";
  } catch (const gmwm::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("c.csv: --data phase: found 16 phase samples, 15 steps, expected at least "
                                         "16 steps"),
              std::string::npos)
        << e.what();
  }
}

TEST(Conditioning, RefusesDecimationAcrossGapsTooFewBlocksAndUnknownWords) {
  gmwm::io::ReadOptions o;
  o.decimate = 4;
  try {
    read_with(ramp_csv(400, 3), o);
    FAIL() << "a record with gaps was decimated";
  } catch (const gmwm::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--decimate 4: found 3 samples missing in 1 gaps, expected a regular record"),
              std::string::npos)
        << e.what();
  }
  o.gaps = gmwm::io::GapHandling::kJoin;
  EXPECT_EQ(read_with(ramp_csv(400, 3), o).signals.front().values.size(), 99u);
  o.decimate = 16;
  EXPECT_THROW(read_with(ramp_csv(200), o), gmwm::InputError);  // 12 blocks
  try {
    gmwm::io::data_kind_of("delta");
    FAIL();
  } catch (const gmwm::InputError& e) {
    EXPECT_STREQ(e.what(),
                 "--data: found 'delta', expected 'rate' (angular rates, specific forces), 'increment' "
                 "(delta-angles, delta-velocities over one sampling period) or 'phase' (a phase or time error, "
                 "an angle)");
  }
  EXPECT_THROW(gmwm::io::decimation_filter_of("sinc"), gmwm::InputError);
  o.decimate = 0;
  EXPECT_EQ(o.Validate(), "--decimate: found 0, expected a whole number from 1 to 1048576");
}

}  // namespace
