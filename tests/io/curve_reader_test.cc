// A given curve's file (io/curve_reader.h): gmwm's own CSVs read as written, the other
// tables' layouts, and every refusal as one line naming the file, line and column.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "gmwm/engine/error.h"
#include "gmwm/io/curve_reader.h"
#include "test_support.h"

namespace gmwm::io {
namespace {

namespace fs = std::filesystem;

std::string write(const std::string& name, const std::string& text) {
  static const test::TempFolder dir("curve_reader");  // removed when the test program ends
  const fs::path p = dir.path / name;
  std::ofstream(p, std::ios::binary) << text;
  return p.string();
}

// The message of read_curves' refusal, with the folder removed ("" when it reads).
std::string refusal(const std::string& name, const std::string& text, const CurveReadOptions& o = {}) {
  const std::string path = write(name, text);
  try {
    read_curves(path, o);
  } catch (const InputError& e) {
    std::string m = e.what();
    const std::string folder = fs::path(path).parent_path().string() + "/";
    if (m.rfind(folder, 0) == 0) m = m.substr(folder.size());
    return m;
  }
  return {};
}

TEST(CurveReader, ReadsGmwmsOwnAllanDeviationCsvOneCurvePerColumn) {
  // gmwm wv --adev-csv's layout: column,m,tau_seconds,adev,ci_low,ci_high,edf.
  const std::string path = write("adev.csv",
                                 "column,m,tau_seconds,adev,ci_low,ci_high,edf\n"
                                 "gyro_x,1,0.01,0.1,0.099,0.101,5000\n"
                                 "gyro_x,2,0.02,0.07,0.069,0.071,2500\n"
                                 "gyro_y,1,0.01,0.2,0.198,0.202,5000\n"
                                 "gyro_y,2,0.02,0.14,0.138,0.142,2500\n");
  const std::vector<GivenCurve> curves = read_curves(path, {});
  ASSERT_EQ(curves.size(), 2u);
  EXPECT_EQ(curves[0].name, "gyro_x");
  EXPECT_EQ(curves[1].name, "gyro_y");
  EXPECT_EQ(curves[0].quantity, CurveQuantity::kAdev);
  EXPECT_EQ(curves[1].tau, (std::vector<double>{0.01, 0.02}));
  EXPECT_EQ(curves[1].value, (std::vector<double>{0.2, 0.14}));
  EXPECT_EQ(curves[1].edf, (std::vector<double>{5000, 2500}));
  EXPECT_EQ(curves[1].low.size(), 2u);
  EXPECT_EQ(curves[1].line, (std::vector<std::int64_t>{4, 5}));
  EXPECT_EQ(curves[1].tau_field.column, 3);
  CurveReadOptions o;
  o.columns = {"gyro_y"};
  EXPECT_EQ(read_curves(path, o).front().name, "gyro_y");
  o.columns = {"gyro_z"};
  EXPECT_EQ(refusal("adev2.csv", "column,tau_seconds,adev\ngyro_x,0.01,0.1\n", o),
            "adev2.csv: --columns: found no curve named 'gyro_z', expected one of: gyro_x");
}

TEST(CurveReader, TakesTauSecondsOverAWvCsvsTauInSamples) {
  // gmwm wv --csv: tau is the scale in samples, tau_seconds in seconds: the latter is read.
  const std::vector<GivenCurve> c = read_curves(write("wv.csv",
                                                      "column,level,tau,tau_seconds,wv,ci_low,ci_high,coefficients\n"
                                                      "x,1,2,0.02,0.5,0.49,0.51,999\n"
                                                      "x,2,4,0.04,0.25,0.24,0.26,997\n"),
                                                {});
  EXPECT_EQ(c.front().quantity, CurveQuantity::kWv);
  EXPECT_EQ(c.front().tau, (std::vector<double>{0.02, 0.04}));
}

TEST(CurveReader, ReadsOtherDelimitersCommentsAByteOrderMarkAndUnitsInTheHeader) {
  for (const std::string& text : {std::string("# from a datasheet\ntau [s]\tADEV\n\n0.1\t0.3\n1\t0.1\n"),
                                  std::string("tau;adev\r\n0.1;0.3\r\n1;0.1\r\n"),
                                  std::string("\xEF\xBB\xBFtau_s   Adev\n 0.1   0.3\n1 0.1\n")}) {
    const std::vector<GivenCurve> c = read_curves(write("delims.txt", text), {});
    ASSERT_EQ(c.size(), 1u) << text;
    EXPECT_EQ(c[0].tau, (std::vector<double>{0.1, 1.0})) << text;
    EXPECT_EQ(c[0].value, (std::vector<double>{0.3, 0.1})) << text;
  }
}

TEST(CurveReader, ReadsAValueColumnAsTheQuantityValueSays) {
  CurveReadOptions o;
  EXPECT_EQ(refusal("value.csv", "tau,value\n1,2\n"),
            "value.csv:1: found a value column (the header: tau, value), expected --value adev, avar or wv to say what "
            "it holds");
  o.quantity = CurveQuantity::kAvar;
  EXPECT_EQ(read_curves(write("value.csv", "tau,value\n1,2\n"), o).front().quantity, CurveQuantity::kAvar);
  EXPECT_EQ(refusal("both.csv", "tau,adev,wv\n1,2,3\n"),
            "both.csv:1: found columns of adev and wv (the header: tau, adev, wv), expected one (--value adev, avar or "
            "wv picks it)");
  o.quantity = CurveQuantity::kWv;
  EXPECT_EQ(read_curves(write("both.csv", "tau,adev,wv\n1,2,3\n"), o).front().value, (std::vector<double>{3.0}));
}

TEST(CurveReader, RefusesWhatIsNoCurveInOneLineNamingItsPlace) {
  EXPECT_EQ(refusal("empty.csv", ""), "empty.csv: found no header, expected a header row naming tau and the values");
  EXPECT_EQ(refusal("onlyheader.csv", "tau,adev\n"),
            "onlyheader.csv: found a header and no point, expected a row of tau and adev per point");
  EXPECT_EQ(refusal("notau.csv", "t,adev\n1,2\n"),
            "notau.csv:1: found no tau column (the header: t, adev), expected one named tau or tau_seconds (seconds)");
  EXPECT_EQ(refusal("novalue.csv", "tau,sigma_x\n1,2\n"),
            "novalue.csv:1: found no value column (the header: tau, sigma_x), expected one named adev, avar, wv or "
            "value");
  EXPECT_EQ(refusal("twotau.csv", "tau,tau,adev\n1,1,2\n"),
            "twotau.csv:1: found two tau columns (1 and 2), expected one");
  EXPECT_EQ(refusal("half.csv", "tau,adev,ci_low\n1,2,1\n"),
            "half.csv:1: found ci_low without ci_high, expected both ends of the intervals or neither");
  EXPECT_EQ(refusal("nan.csv", "tau,adev\n1,0.1\n2,nan\n"),
            "nan.csv:3:2: found 'nan', expected the adev (a finite decimal number)");
  EXPECT_EQ(refusal("huge.csv", "tau,adev\n1,1e999\n"),
            "huge.csv:2:2: found '1e999' (beyond a double), expected the adev (a finite decimal number)");
  EXPECT_EQ(refusal("short.csv", "tau,adev\n1\n"), "short.csv:2:2: found 1 fields, expected the adev in field 2");
  EXPECT_EQ(refusal("neg.csv", "tau,adev\n1,0.1\n2,-0.1\n"),
            "neg.csv:3:2: found -0.1, expected a positive finite adev");
  EXPECT_EQ(refusal("dup.csv", "tau,adev\n1,0.1\n1,0.09\n4,0.1\n"),
            "dup.csv:3:1: found tau 1 s again (line 2), expected each tau once, increasing");
  EXPECT_EQ(refusal("down.csv", "tau,adev\n1,0.1\n0.5,0.09\n"),
            "down.csv:3:1: found tau 0.5 s after 1 s, expected taus increasing");
  EXPECT_EQ(refusal("outside.csv", "tau,adev,ci_low,ci_high\n1,0.1,0.11,0.2\n"),
            "outside.csv:2:3: found the interval 0.11 .. 0.2 for 0.1, expected low < high holding the value");
  EXPECT_EQ(refusal("edf.csv", "tau,adev,edf\n1,0.1,-3\n"),
            "edf.csv:2:3: found -3, expected degrees of freedom above 0, up to 1e+12");
  EXPECT_EQ(refusal("nul.csv", std::string("tau,adev\n1,0.1\0\n", 15)),
            "nul.csv: found a NUL byte (binary data), expected a curve as delimited text");
  const std::string missing = refusal("missing/none.csv", "");  // no folder "missing": nothing written
  EXPECT_EQ(missing.rfind("none.csv: ", 0), 0u) << missing;
  EXPECT_NE(missing.find("expected a curve (delimited text of tau and its values)"), std::string::npos) << missing;
}

TEST(CurveReader, ReadsNamedColumnsAsAFileOfThemWouldBe) {
  CurveReadOptions o;
  const GivenCurve c = curve_from_columns({"tau", "adev", "ci_low", "ci_high"},
                                          {{1, 2}, {0.2, 0.1}, {0.19, 0.09}, {0.21, 0.11}}, "curve", o);
  EXPECT_EQ(c.name, "adev");
  EXPECT_EQ(c.low, (std::vector<double>{0.19, 0.09}));
  EXPECT_TRUE(c.line.empty());
  try {
    curve_from_columns({"tau", "adev"}, {{1, 1}, {0.2, 0.1}}, "curve", o);
    FAIL() << "a repeated tau was read";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "curve: tau[1]: found tau 1 s again (tau[0]), expected each tau once, increasing");
  }
}

}  // namespace
}  // namespace gmwm::io
