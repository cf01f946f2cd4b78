// Hostile corpus, issue 25's "wrong results given silently": inputs that were once read or
// exported without a word and now get one line and exit 2 (hostile_harness.h): results
// whose unit is unknown, records whose rate changes, text after a gzip stream, values whose
// wavelet variance underflows or overflows a double, text in another encoding or with
// CR-only line endings.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "hostile_harness.h"

using namespace gmwm::test::hostile;

namespace {

// 4096 rows of time, gyro_x, accel_x at 100 Hz, the signals scaled by `scale`.
std::string scaled_csv(double scale) {
  std::string s = "time,gyro_x,accel_x\n";
  char buf[160];
  for (int i = 0; i < 4096; ++i) {
    std::snprintf(buf, sizeof buf, "%.2f,%.17g,%.17g\n", i * 0.01, scale * (std::sin(i * 0.37) + (i % 7) * 0.1),
                  scale * (9.81 + std::cos(i * 0.11)));
    s += buf;
  }
  return s;
}

// A fit result of one gyro column; `unit` is the JSON value of "unit" ("" leaves it out).
std::string fit_result(const std::string& unit) {
  return std::string(R"J({"tool": "gmwm", "version": "0.1.0", "command": "fit", "input": "d.csv", "columns": [)J") +
         R"J({"name": "gyro_x", "n": 4096, "freq": 100.0, "model": "WN(sigma2=1e-4)+RW(gamma2=1e-10)", )J" +
         (unit.empty() ? "" : "\"unit\": " + unit + ", ") + R"J("status": "converged"}]})J";
}

std::vector<Case> corpus() {
  const auto base = file("base.csv", base_csv());
  std::string rate_change = "time,gyro_x\n";
  for (int i = 0; i < 6000; ++i)
    rate_change += std::to_string(i < 3000 ? i * 0.01 : 30.0 + (i - 3000) * 0.005) + "," +
                   std::to_string(std::sin(i * 0.37)) + "\n";
  std::string more_rows;
  for (int i = 4096; i < 4200; ++i) more_rows += std::to_string(i * 0.01) + ",0.001,9.81\n";
  std::string utf16 = "\xFF\xFE";
  for (char c : base_csv().substr(0, 2000)) utf16 += std::string(1, c) + '\0';
  std::string ten_ghz = "time,gyro_x\n";  // stamps 0.1 ns apart
  char stamp[64];
  for (int i = 0; i < 4096; ++i) {
    std::snprintf(stamp, sizeof stamp, "%.17g,%.6f\n", i * 1e-10, std::sin(i * 0.37));
    ten_ghz += stamp;
  }
  std::string epoch_ghz = "time,gyro_x\n";  // 1 GHz on seconds since 1970, held to 0.24 us
  for (int i = 0; i < 4096; ++i) {
    std::snprintf(stamp, sizeof stamp, "1700000000.%09d,%.6f\n", i, std::sin(i * 0.37));
    epoch_ghz += stamp;
  }
  std::string cr_only = base_csv();
  for (char& c : cr_only)
    if (c == '\n') c = '\r';
  return {
      {"export of a result that does not say its unit",
       {"export", "r.json", "--format", "kalibr", "--output", "o.yaml"},
       {"r.json: column 'gyro_x': the result does not say the data's unit", "--units gyro=UNIT"},
       file("r.json", fit_result(""))},
      {"export of a result whose unit is null",
       {"export", "r.json", "--format", "gz-sdf", "--output", "o.sdf"},
       {"column 'gyro_x'", "does not say the data's unit"},
       file("r.json", fit_result("null"))},
      {"export units contradicting the result's",
       {"export", "r.json", "--format", "kalibr", "--units", "gyro=rad/s", "--output", "o.yaml"},
       {"--units says gyro=rad/s, but the result was fitted on deg/s data"},
       file("r.json", fit_result("\"deg/s\""))},
      {"export units naming only the other sensor",
       {"export", "r.json", "--format", "kalibr", "--units", "accel=g", "--output", "o.yaml"},
       {"column 'gyro_x'", "--units gyro=UNIT"},
       file("r.json", fit_result(""))},
      {"export of a result with a unit of the wrong sensor",
       {"export", "r.json", "--format", "kalibr", "--output", "o.yaml"},
       {"column 'gyro_x'", "\"unit\"", "'g' for gyro"},
       file("r.json", fit_result("\"g\""))},
      {"export of a result with a numeric unit",
       {"export", "r.json", "--format", "kalibr", "--output", "o.yaml"},
       {"column 'gyro_x'", "found \"unit\": number"},
       file("r.json", fit_result("57.3"))},
      {"export of a data file that does not say its unit",
       {"export", "base.csv", "--model", "WN+RW", "--format", "kalibr", "--output", "o.yaml"},
       {"base.csv: column 'gyro_x': the file does not say its unit; give --units gyro=UNIT"},
       base},
      {"joint fit with bad units",
       {"fit", "base.csv", "--joint", "b.csv", "--model", "WN+RW", "--units", "gyro=rpm"},
       {"--units", "'rpm'"},
       both(base, file("b.csv", scaled_csv(2.0)))},
      {"joint select with bad units",
       {"select", "base.csv", "--joint", "b.csv", "--model", "WN+RW", "--units", "gyro=deg/s,accel=furlong"},
       {"--units", "'furlong'"},
       both(base, file("b.csv", scaled_csv(2.0)))},
      {"rate change inside a record",
       {"wv", "rc.csv"},
       {"rc.csv: timestamps 'time'", "from about 100 Hz at its start to about 200 Hz", "--freq"},
       file("rc.csv", rate_change)},
      {"rate change inside a gzip record",
       {"fit", "rc.csv.gz", "--model", "WN"},
       {"rc.csv.gz", "100 Hz", "200 Hz"},
       file("rc.csv.gz", gzip_member(rate_change))},
      {"timestamps beyond the largest sampling rate",
       {"wv", "g.csv"},
       {"g.csv: timestamps 'time' in s", "= 1e+10 Hz, expected a sampling rate in Hz from 1e-09 to 1e+09", "--freq"},
       file("g.csv", ten_ghz)},
      {"stamps finer than a double holds at their magnitude",
       {"wv", "e.csv"},
       {"e.csv: timestamps 'time'", "doubles hold stamps near 1.7e+09 s only to 0.2384 us",
        "too coarse to resolve the sampling rate", "--freq"},
       file("e.csv", epoch_ghz)},
      {"plain rows after a gzip member",
       {"wv", "m.csv.gz"},
       {"m.csv.gz: found bytes that are not gzip data after the end of the gzip stream, at byte offset"},
       file("m.csv.gz", gzip_member(base_csv()) + more_rows)},
      {"values whose squares underflow",
       {"wv", "tiny.csv"},
       {"tiny.csv: column 'gyro_x': the wavelet variance is zero at every level although the values vary", "rescale"},
       file("tiny.csv", scaled_csv(1e-300))},
      {"values whose squares underflow, fitted",
       {"fit", "tiny.csv", "--model", "WN+RW"},
       {"tiny.csv: column 'gyro_x'", "underflow"},
       file("tiny.csv", scaled_csv(1e-300))},
      {"values whose sums of squares overflow",
       {"fit", "huge.csv", "--model", "WN+RW"},
       {"huge.csv: column 'gyro_x': the wavelet variance at level", "rescale"},
       file("huge.csv", scaled_csv(1e160))},
      {"values too small for a fit",
       {"select", "small.csv", "--model", "WN+RW"},
       {"small.csv: column 'gyro_x': the wavelet variance at level", "outside 1e-30 .. 1e+30"},
       file("small.csv", scaled_csv(1e-20))},
      {"values too large for a fit",
       {"gap", "big.csv", "--model", "WN(sigma2=1)"},
       {"big.csv: column 'gyro_x'", "outside 1e-30 .. 1e+30"},
       file("big.csv", scaled_csv(1e20))},
      {"UTF-16 with a byte-order mark",
       {"wv", "u.csv"},
       {"u.csv:1: found a UTF-16 byte-order mark", "iconv"},
       file("u.csv", utf16)},
      {"UTF-16 without a byte-order mark",
       {"wv", "u.csv"},
       {"u.csv:1: found NUL bytes in the header line", "UTF-16"},
       file("u.csv", utf16.substr(2))},
      {"CR-only line endings",
       {"wv", "mac.csv"},
       {"mac.csv:1: found carriage returns (CR)", "CR-only"},
       file("mac.csv", cr_only)},
  };
}

}  // namespace

HOSTILE_CORPUS(HostileRecords, corpus());
