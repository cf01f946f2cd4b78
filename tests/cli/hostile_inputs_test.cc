// The bad-input contract against a corpus of hostile inputs and options: each case exits
// 2 with exactly one line "gmwm: error: ..." naming the file or option and what was
// expected, writes nothing to stdout, creates or changes no file in its folder, and runs
// in under kMaxSeconds with the program's peak memory under kMaxRssBytes.
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "hostile_harness.h"

namespace fs = std::filesystem;
using namespace gmwm::test::hostile;
using gmwm::test::write_text;

namespace {

const std::string kYamlWithoutGyroDensity =
    "accelerometer_noise_density: 4.9e-03\naccelerometer_random_walk: 3.0e-04\n"
    "gyroscope_random_walk: 2.0e-05\nupdate_rate: 100.0\n";
const std::string kYaml = kYamlWithoutGyroDensity + "gyroscope_noise_density: 8.73e-04\n";

// A gz-sensors IMU whose gyro x noise block (line 5) holds `figures`.
std::string gz_sdf(const std::string& figures) {
  return "<sdf version=\"1.9\">\n<sensor name=\"imu\" type=\"imu\">\n<imu>\n<angular_velocity>\n"
         "<x><noise type=\"gaussian\">" +
         figures + "</noise></x>\n</angular_velocity>\n</imu>\n</sensor>\n</sdf>\n";
}

std::vector<Case> corpus() {
  const std::string rows = base_csv();
  const auto base = file("base.csv", rows);
  const std::string head = "time,gyro_x,accel_x\n";
  std::vector<Case> c = {
      // --- outputs ---------------------------------------------------------------------
      {"output equal to the input", {"wv", "base.csv", "--csv", "base.csv"}, {"base.csv"}, base},
      {"json over the input", {"fit", "base.csv", "--model", "WN", "--json", "base.csv"}, {"--json", "base.csv"}, base},
      {"two outputs, one file", {"wv", "base.csv", "--json", "o.json", "--csv", "o.json"}, {"o.json"}, base},
      {"output to a folder",
       {"wv", "base.csv", "--json", "sub"},
       {"sub"},
       both(base, [](const fs::path& d) { fs::create_directory(d / "sub"); })},
      {"output through a symlink",
       {"wv", "base.csv", "--json", "link.json"},
       {"link.json"},
       both(base, [](const fs::path& d) { fs::create_symlink(d / "target.json", d / "link.json"); })},
      {"output to a FIFO",
       {"wv", "base.csv", "--json", "pipe.json"},
       {"pipe.json"},
       both(base, [](const fs::path& d) { ::mkfifo((d / "pipe.json").c_str(), 0600); })},
      {"output to a device", {"wv", "base.csv", "--json", "/dev/full"}, {"/dev/full"}, base},
      {"output in a missing folder", {"wv", "base.csv", "--json", "nowhere/o.json"}, {"nowhere"}, base},
      {"partial outputs", {"wv", "base.csv", "--csv", "ok.csv", "--json", "/proc/x/o.json"}, {"/proc/x"}, base},
      {"simulate output equal to json",
       {"simulate", "--model", "WN(sigma2=1)", "--n", "100", "--output", "x.csv", "--json", "x.csv"},
       {"x.csv"}},
      // --- reading ---------------------------------------------------------------------
      {"missing input", {"wv", "nothere.csv", "--freq", "100"}, {"nothere.csv", "not found"}},
      {"folder as input",
       {"wv", "sub", "--freq", "100"},
       {"sub", "folder"},
       [](const fs::path& d) { fs::create_directory(d / "sub"); }},
      {"missing log with a topic",
       {"wv", "flight.ulg", "--topic", "sensor_gyro"},
       {"flight.ulg: file not found, expected an existing data file"}},
      {"folder with a topic",
       {"fit", "bag", "--model", "WN", "--topic", "/imu"},
       {"bag: is a folder, expected a data file"},
       [](const fs::path& d) { fs::create_directory(d / "bag"); }},
      {"empty file", {"wv", "empty.csv", "--freq", "100"}, {"empty.csv"}, file("empty.csv", "")},
      {"header only", {"wv", "h.csv", "--freq", "100"}, {"h.csv"}, file("h.csv", "a,b\n")},
      {"NUL in a cell",
       {"wv", "n.csv"},
       {"n.csv:3:2", "\\x00", "expected a number"},
       file("n.csv", head + "0,1,2\n0.01," + bytes({0}) + "x,3\n")},
      {"binary junk in a cell",
       {"wv", "b.csv"},
       {"b.csv:3:2", "\\x01\\xFF", "expected a number"},
       file("b.csv", head + "0,1,2\n0.01," + bytes({1, 0xff, 0xfe}) + ",3\n")},
      {"text in a cell",
       {"wv", "t.csv"},
       {"t.csv:3:3", "'oops'", "expected a number"},
       file("t.csv", head + "0,1,2\n0.01,2,oops\n")},
      {"NaN in a cell", {"wv", "t.csv"}, {"t.csv:3:2", "NaN"}, file("t.csv", head + "0,1,2\n0.01,nan,3\n")},
      {"out-of-range number", {"wv", "t.csv"}, {"t.csv:3:2", "1e999"}, file("t.csv", head + "0,1,2\n0.01,1e999,3\n")},
      {"ragged row", {"wv", "t.csv"}, {"t.csv:3"}, file("t.csv", head + "0,1,2\n0.01,2,3,4\n")},
      {"too few rows", {"wv", "t.csv"}, {"t.csv", "16"}, file("t.csv", head + "0,1,2\n0.01,2,3\n")},
      {"constant column",
       {"wv", "c.csv", "--freq", "100"},
       {"c.csv", "constant"},
       file("c.csv",
            [] {
              std::string s = "a\n";
              for (int i = 0; i < 64; ++i) s += "1.5\n";
              return s;
            }())},
      {"truncated gzip",
       {"wv", "t.csv.gz", "--freq", "100"},
       {"t.csv.gz", "gzip"},
       file("t.csv.gz", bytes({0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 3, 0x4b, 0x4c}))},
      {"corrupt gzip",
       {"wv", "c.csv.gz", "--freq", "100"},
       {"c.csv.gz", "gzip"},
       file("c.csv.gz", bytes({0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 3, 0xff, 0xff, 0xff, 0xff, 0, 0, 0, 0}))},
      // --- limits (docs/cli.md "Limits") -------------------------------------------------
      {"10 MB line",
       {"wv", "l.csv"},
       {"l.csv:3", "line longer than 1048576 bytes"},
       file("l.csv", head + "0,1,2\n0.01," + std::string(10'000'000, '7') + ",3\n")},
      {"1e6 columns",
       {"wv", "w.csv", "--freq", "100"},
       {"w.csv:1", "line longer than"},
       file("w.csv",
            [] {
              std::string s;
              for (int k = 0; k < 1'000'000; ++k) s += (k ? ",c" : "c") + std::to_string(k);
              return s + "\n";
            }())},
      {"5000 columns",
       {"wv", "w.csv", "--freq", "100"},
       {"w.csv:1", "found 5000 columns, expected at most 4096"},
       file("w.csv",
            [] {
              std::string h, r;
              for (int k = 0; k < 5000; ++k) {
                h += (k ? ",c" : "c") + std::to_string(k);
                r += k ? ",1" : "1";
              }
              return h + "\n" + r + "\n" + r + "\n";
            }())},
      {"gzip bomb of zeros (1 GB, no line break)",
       {"wv", "z.csv.gz", "--freq", "100"},
       {"z.csv.gz:1", "line longer than"},
       file("z.csv.gz", gzip_bomb("", std::string(1, '0'), 1024))},
      {"gzip bomb of rows (1 GB)",
       {"wv", "r.csv.gz", "--freq", "100"},
       {"r.csv.gz", "more than 250 times", "decompression bomb"},
       file("r.csv.gz",
            gzip_bomb("x\n", "1.00000000000000000000000000000000000000000000000000000000000000000000001\n", 1024))},
      {"gzip bomb of blank lines after the data (1 GB)",
       {"wv", "b.csv.gz"},
       {"b.csv.gz", "more than 250 times"},
       file("b.csv.gz", gzip_bomb(rows, "\n", 1024))},
      {"gzip bomb of blank lines of spaces, tabs and CR LF after the data (1 GB)",
       {"wv", "s.csv.gz"},
       {"s.csv.gz", "more than 250 times"},
       file("s.csv.gz", gzip_bomb(rows, " \t\r\n", 1024))},
      {"no temporary folder for a record beyond --memory",
       {"wv", "long.csv", "--memory", "1"},
       {"temporary folder '/nonexistent/gmwm-tmp'", "set TMPDIR"},
       file("long.csv",
            [] {
              std::string s = "time,gyro_x,accel_x\n";
              for (int i = 0; i < 70000; ++i)
                s += std::to_string(i) + "," + std::to_string(i % 13) + "," + std::to_string(i % 7) + "\n";
              return s;
            }()),
       {"export TMPDIR=/nonexistent/gmwm-tmp;"}},
      {"zero memory",
       {"wv", "base.csv", "--memory", "0"},
       {"--memory: found '0', expected a number of MB from 1"},
       base},
      {"levels beyond the series",
       {"wv", "base.csv", "--levels", "40"},
       {"base.csv: --levels 40: the signals have 4096 samples, which give at most 12 levels"},
       base},
      {"FIFO with no writer",
       {"wv", "fifo", "--freq", "100"},
       {"fifo", "no writer"},
       [](const fs::path& d) { ::mkfifo((d / "fifo").c_str(), 0600); }},
      {"unknown column", {"wv", "base.csv", "--columns", "nosuch"}, {"base.csv", "nosuch"}, base},
      {"empty column list", {"wv", "base.csv", "--columns", ""}, {"--columns", "empty list"}, base},
      {"empty column entry", {"wv", "base.csv", "--columns", "gyro_x,,accel_x"}, {"--columns", "empty"}, base},
      {"zero rate", {"wv", "base.csv", "--freq", "0"}, {"--freq", "from 1e-09 to 1e+09"}, base},
      {"negative rate", {"wv", "base.csv", "--freq=-1"}, {"--freq", "from 1e-09"}, base},
      {"subnormal rate", {"wv", "base.csv", "--freq", "1e-320"}, {"--freq", "from 1e-09"}, base},
      {"NaN rate", {"wv", "base.csv", "--freq", "nan"}, {"--freq"}, base},
      {"zero levels", {"wv", "base.csv", "--levels", "0"}, {"--levels"}, base},
      {"alpha of zero", {"wv", "base.csv", "--alpha", "0"}, {"alpha"}, base},
      {"alpha above one", {"wv", "base.csv", "--alpha", "1.5"}, {"alpha"}, base},
      {"topic on a CSV", {"wv", "base.csv", "--topic", "/imu"}, {"base.csv", "--topic"}, base},
      {"ULog magic then junk",
       {"wv", "x.ulg"},
       {"x.ulg"},
       file("x.ulg", std::string("ULog\x01\x12\x35", 7) + std::string(9, '\0') + "junkjunkjunk")},
      {"ROS bag header cut", {"wv", "x.bag"}, {"x.bag"}, file("x.bag", "#ROSBAG V2.0\n\x45\x00\x00")},
      {"old ROS bag version", {"wv", "x.bag"}, {"x.bag", "1.2"}, file("x.bag", "#ROSBAG V1.2\nxxxxxxxx")},
      {"MCAP magic then junk",
       {"wv", "x.mcap"},
       {"x.mcap"},
       file("x.mcap", std::string("\x89MCAP0\r\n", 8) + "\x01\xff\xff\xff\xff\xff\xff\xff\x7f")},
      {"SQLite file without bag tables",
       {"wv", "x.db3"},
       {"x.db3"},
       file("x.db3", std::string("SQLite format 3\0", 16) + std::string(100, '\0'))},
      // --- models ----------------------------------------------------------------------
      {"unknown process", {"fit", "base.csv", "--model", "AR1+FOO"}, {"AR1+FOO", "FOO"}, base},
      {"huge repeat count",
       {"fit", "base.csv", "--model", "99999999999999999999*AR1"},
       {"repeat count 99999999999999999999", "from 1 to"},
       base},
      {"repeat count with leading zeros",
       {"fit", "base.csv", "--model", "0000012*AR1+WN"},
       {"'0000012'", "leading zeros"},
       base},
      {"empty model", {"fit", "base.csv", "--model", ""}, {"model"}, base},
      {"ARMA order overflowing an integer (found by fuzzing)",
       {"fit", "base.csv", "--model", "ARMA(p=1e300,q=1)"},
       {"ARMA: p must be an integer from 0 to 1000 (got 1e+300)"},
       base},
      {"trailing plus", {"fit", "base.csv", "--model", "WN+"}, {"WN+"}, base},
      {"invalid parameter value",
       {"simulate", "--model", "AR1(phi=2,sigma2=1)", "--n", "100", "--output", "s.csv"},
       {"AR1", "phi"}},
      {"model without values",
       {"simulate", "--model", "WN", "--n", "100", "--output", "s.csv"},
       {"--model 'WN'", "sigma2"}},
      {"more parameters than levels",
       {"fit", "t.csv", "--freq", "100", "--model", "4*AR1+WN+RW+QN+DR"},
       {"level"},
       file("t.csv",
            [] {
              std::string s = "a\n";
              for (int i = 0; i < 40; ++i) s += std::to_string(std::sin(i * 1.3)) + "\n";
              return s;
            }())},
      // --- simulate --------------------------------------------------------------------
      {"timestamp name for a signal",
       {"simulate", "--model", "WN(sigma2=1)", "--n", "100", "--names", "time", "--freq", "10", "--output", "s.csv"},
       {"--names", "'time'"}},
      {"duplicate names",
       {"simulate", "--model", "WN(sigma2=1)", "--n", "100", "--signals", "2", "--names", "a,a", "--output", "s.csv"},
       {"--names", "twice"}},
      {"name with a newline",
       {"simulate", "--model", "WN(sigma2=1)", "--n", "100", "--names", "a\nb: 1", "--output", "s.csv"},
       {"--names", "control"}},
      {"more samples than memory",
       {"simulate", "--model", "WN(sigma2=1)", "--n", "1000000000000", "--output", "s.csv"},
       {"--n 1000000000000", "GB"}},
      {"zero samples", {"simulate", "--model", "WN(sigma2=1)", "--n", "0"}, {"--n"}},
      {"quantum below the normal doubles",
       {"simulate", "--model", "WN(sigma2=1)", "--n", "100", "--quantum", "1e-320", "--output", "s.csv"},
       {"--quantum", "at least 2.2e-308"}},
      {"drift beyond a double",
       {"simulate", "--model", "DR(omega=1e305)", "--n", "10000", "--output", "s.csv"},
       {"--model 'DR(omega=1e305)' with --n 10000", "beyond the largest double"}},
      {"quantum rounding beyond a double",
       {"simulate", "--model", "DR(omega=1.8e306)", "--n", "100", "--quantum", "1e308", "--output", "s.csv"},
       {"--quantum", "beyond the largest double"}},
      // --- nav -------------------------------------------------------------------------
      {"nav errors beyond a double",
       {"nav", "--truth", "gyro=WN(sigma2=1e300);accel=WN(sigma2=1e-6)", "--rate", "100", "--fix-rate", "0", "--json",
        "n.json"},
       {"truth", "overflow a double", "horizon"}},
      {"nav filter whose densities overflow once squared",
       {"nav", "--truth", "gyro=WN(sigma2=1e-6);accel=WN(sigma2=1e-6)", "--filter", "wnrw*1e160", "--rate", "100",
        "--json", "n.json"},
       {"wnrw*1e160", "overflow a double"}},
      // --- plan ------------------------------------------------------------------------
      {"plan of terms no double scale holds",
       {"plan", "--model", "WN(sigma2=1e-300)+RW(gamma2=1e300)", "--freq", "100", "--json", "p.json"},
       {"WN(sigma2=1e-300)", "spans more scales than a double holds"}},
      // --- gap and simulator configurations --------------------------------------------
      {"two baselines", {"gap", "base.csv", "--model", "WN(sigma2=1)", "--fit", "WN"}, {"--"}, base},
      {"too few replicates",
       {"gap", "base.csv", "--model", "WN(sigma2=1)", "--replicates", "5"},
       {"--replicates"},
       base},
      {"missing Kalibr file", {"gap", "base.csv", "--kalibr", "none.yaml"}, {"none.yaml"}, base},
      {"Kalibr value out of range",
       {"gap", "base.csv", "--kalibr", "k.yaml"},
       {"k.yaml:1"},
       both(base, file("k.yaml", "gyroscope_noise_density: 1e300\n" + kYamlWithoutGyroDensity))},
      {"Kalibr duplicate key",
       {"gap", "base.csv", "--kalibr", "k.yaml"},
       {"k.yaml", "gyroscope_noise_density"},
       both(base, file("k.yaml", kYaml + "gyroscope_noise_density: 1.0e-3\n"))},
      {"Kalibr hex float",
       {"gap", "base.csv", "--kalibr", "k.yaml"},
       {"k.yaml:1"},
       both(base, file("k.yaml", "gyroscope_noise_density: 0x1p-10\n" + kYamlWithoutGyroDensity))},
      {"invalid YAML", {"gap", "base.csv", "--kalibr", "k.yaml"}, {"k.yaml"}, both(base, file("k.yaml", "a: [1, 2\n"))},
      // 200 rows, then one stamp 1e5 s later: a grid of 1e7 samples the reference would simulate.
      {"a far stamp making a grid to simulate 50000 times the record",
       {"gap", "far.csv", "--model", "WN(sigma2=1)"},
       {"far.csv", "gap diagnosis simulates the record's whole grid", "--gaps join"},
       file("far.csv",
            [] {
              std::string t = "time [s],gyro_x\n";
              for (int k = 0; k < 200; ++k)
                t += std::to_string((k < 100 ? k : k + 9999900) / 100.0) + "," + std::to_string((k * 37 % 11) - 5) +
                     "\n";
              return t;
            }())},
      {"invalid SDF", {"gap", "base.csv", "--gazebo", "s.sdf"}, {"s.sdf"}, both(base, file("s.sdf", "<sdf><model>"))},
      // gmwm stability: a tau no integer holds, a phase joined across its gaps, every tau of a long record.
      {"a stability tau of 1e300 s",
       {"stability", "base.csv", "--taus", "1e300"},
       {"--taus: 1e+300 s", "beyond"},
       base},
      {"phase joined across a gap",
       {"stability", "far.csv", "--data", "phase", "--gaps", "join"},
       {"far.csv: --data phase: found 1 gaps", "cut the record at its gaps"},
       file("far.csv",
            [] {
              std::string t = "time [s],x\n";
              for (int k = 0; k < 200; ++k)
                t += std::to_string((k < 100 ? k : k + 50) / 100.0) + "," + std::to_string(k) + "\n";
              return t;
            }())},
      {"every Theo1 tau of a record of 2^18 samples",
       {"stability", "long.csv", "--freq", "100", "--kind", "theo1", "--taus", "all"},
       {"long.csv: --taus all", "give octave, decade, a list of times or fewer kinds"},
       file("long.csv",
            [] {
              std::string t = "y\n";
              for (int k = 0; k < (1 << 18); ++k) t += std::to_string(k % 7) + "\n";
              return t;
            }())},
      {"datasheet figure without a unit",
       {"gap", "base.csv", "--datasheet", "d.yaml"},
       {"d.yaml:2", "without a unit"},
       both(base, file("d.yaml", "gyroscope:\n  noise_density: 0.05\n"))},
      {"datasheet unit of the wrong dimension",
       {"gap", "base.csv", "--datasheet", "d.yaml"},
       {"d.yaml:2", "not a unit of a white noise density"},
       both(base, file("d.yaml", "gyroscope:\n  noise_density: 25 deg/h\n"))},
      {"datasheet figure beyond a double",
       {"gap", "base.csv", "--datasheet", "d.yaml"},
       {"d.yaml:2"},
       both(base, file("d.yaml", "gyroscope:\n  noise_density: 1e999 deg/s/sqrt(Hz)\n"))},
      {"datasheet figure whose variance overflows",
       {"gap", "base.csv", "--datasheet", "d.yaml"},
       {"d.yaml"},
       both(base, file("d.yaml", "gyroscope:\n  in_run_bias_stability: 1e300 deg/s\n"))},
      {"SDF stddev whose variance overflows",
       {"gap", "base.csv", "--gazebo", "s.sdf"},
       {"--gazebo s.sdf:5: angular_velocity/x/noise/stddev: 1e+308 rad/s gives WN sigma2 = inf per sample",
        "expected a figure near the sensor's"},
       both(base, file("s.sdf", gz_sdf("<stddev>1e308</stddev>")))},
      {"SDF stddev whose variance underflows",
       {"gap", "base.csv", "--gazebo", "s.sdf"},
       {"s.sdf:5: angular_velocity/x/noise/stddev: 1e-170 rad/s gives WN sigma2 = 0 per sample"},
       both(base, file("s.sdf", gz_sdf("<stddev>1e-170</stddev>")))},
      {"SDF stddev below a double's normal numbers",
       {"gap", "base.csv", "--gazebo", "s.sdf"},
       {"s.sdf:5: angular_velocity/x/noise/stddev: found 1e-320, beyond the range of a double"},
       both(base, file("s.sdf", gz_sdf("<stddev>1e-320</stddev>")))},
      {"SDF precision whose rounding variance overflows",
       {"gap", "base.csv", "--gazebo", "s.sdf"},
       {"s.sdf:5: angular_velocity/x/noise/precision: 1e+200 rad/s gives a rounding variance"},
       both(base, file("s.sdf", gz_sdf("<stddev>0.01</stddev><precision>1e200</precision>")))},
      {"SDF dynamic bias a double cannot tell from a random walk",
       {"gap", "base.csv", "--gazebo", "s.sdf"},
       {"s.sdf:5: angular_velocity/x/noise/dynamic_bias_correlation_time: 1e+308 s", "rounds to 1"},
       both(base, file("s.sdf", gz_sdf("<dynamic_bias_stddev>2e-5</dynamic_bias_stddev>"
                                       "<dynamic_bias_correlation_time>1e308</dynamic_bias_correlation_time>")))},
      {"RotorS noise density whose variance overflows",
       {"gap", "base.csv", "--gazebo", "r.sdf"},
       {"r.sdf:2: gyroscopeNoiseDensity: 1e+308 rad/s/sqrt(Hz) gives WN sigma2 = inf per sample"},
       both(base, file("r.sdf",
                       "<plugin name=\"imu\">\n<gyroscopeNoiseDensity>1e308</gyroscopeNoiseDensity>\n"
                       "</plugin>\n"))},
      {"nav truth from an SDF whose variance overflows",
       {"nav", "--truth", "s.sdf", "--rate", "100", "--json", "n.json"},
       {"s.sdf:5: angular_velocity/x/noise/stddev", "outside the range of a double"},
       file("s.sdf", gz_sdf("<stddev>1e308</stddev>"))},
      {"Kalibr figure below a double's normal numbers",
       {"gap", "base.csv", "--kalibr", "k.yaml"},
       {"k.yaml:1: gyroscope_noise_density", "WN sigma2 = 0 per sample", "outside the range of a double"},
       both(base, file("k.yaml", "gyroscope_noise_density: 1e-320\n" + kYamlWithoutGyroDensity))},
      {"datasheet figure that underflows in SI units",
       {"gap", "base.csv", "--datasheet", "d.yaml"},
       {"d.yaml:3: gyroscope.bias_instability: found 1e-320 deg/h, which is 0 in SI units (rad/s)"},
       both(base,
            file("d.yaml", "gyroscope:\n  noise_density: 1e-3 rad/s/sqrt(Hz)\n  bias_instability: 1e-320 deg/h\n"))},
      {"datasheet figure beyond a double in SI units",
       {"gap", "base.csv", "--datasheet", "d.yaml"},
       {"d.yaml:2: accelerometer.bias_instability: found 1e308 g, which is inf in SI units (m/s^2)"},
       both(base, file("d.yaml", "accelerometer:\n  bias_instability: 1e308 g\n"))},
      {"bad units",
       {"gap", "base.csv", "--model", "WN(sigma2=1)", "--units", "gyro=furlong"},
       {"--units", "furlong"},
       base},
      // --- robust and options ----------------------------------------------------------
      {"efficiency without robust", {"wv", "base.csv", "--eff", "0.8"}, {"--eff", "--robust"}, base},
      {"efficiency above one", {"wv", "base.csv", "--robust", "--eff", "1.5"}, {"--eff"}, base},
      {"unknown option", {"wv", "base.csv", "--frobnicate"}, {"--frobnicate"}, base},
      {"unknown command", {"frobnicate"}, {"unknown command 'frobnicate'", "wv, fit"}},
      // --- export ----------------------------------------------------------------------
      {"unknown export format",
       {"export", "base.csv", "--model", "WN+RW", "--format", "nope", "--output", "o.yaml"},
       {"--format"},
       base},
      {"rostopic with a newline",
       {"export", "base.csv", "--model", "WN+RW", "--format", "kalibr", "--rostopic", "/imu\nrate: 1", "--output",
        "o.yaml"},
       {"--rostopic", "ROS topic name"},
       base},
      {"Kalman rate absurd",
       {"fit", "base.csv", "--model", "WN+RW", "--kf-rate=-1e300"},
       {"--kf-rate: found -1e+300, expected a sampling rate in Hz from 1e-09 to 1e+09"},
       base},
      {"numeric model in an export source",
       {"export", "r.json", "--format", "kalibr", "--output", "o.yaml"},
       {"r.json: column 'x': found \"model\": number, expected a model string"},
       file("r.json", R"({"tool": "gmwm", "version": "0.1.0", "command": "fit", "input": "d.csv", "columns": [)"
                      R"({"name": "x", "n": 4096, "freq": 100.0, "model": 5, "status": "converged"}]})")},
      {"number beyond a double in an export source (found by fuzzing)",
       {"export", "r.json", "--format", "kalibr", "--output", "o.yaml"},
       {"r.json: invalid JSON"},
       file("r.json", R"({"tool": "gmwm", "command": "fit", "columns": [{"name": "x", "n": 1e999}]})")},
      {"export over its source",
       {"export", "base.csv", "--model", "WN+RW", "--format", "kalibr", "--output", "base.csv"},
       {"base.csv"},
       base},
  };
  return c;
}

}  // namespace

HOSTILE_CORPUS(Hostile, corpus());

TEST(HostileCorpus, HoldsAtLeastSixtyCases) { EXPECT_GE(corpus().size(), 60u); }
