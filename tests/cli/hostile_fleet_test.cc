// Hostile corpus, fleets (issue 42): crafted manifests (encodings, NUL bytes, huge fields,
// duplicate units, paths that climb out or name devices, unknown columns, malformed CSV and
// YAML), bad spec and baseline files, caches that cannot be one and outputs over the inputs.
// Each is refused before any work (hostile_harness.h): exit 2, one line naming the file and
// the row or field, nothing on stdout, nothing created or changed (no cache folder either).
#include <string>
#include <vector>

#include <filesystem>

#include <gtest/gtest.h>

#include "hostile_harness.h"

using namespace gmwm::test::hostile;

namespace {

namespace fs = std::filesystem;

// `gmwm fleet MANIFEST --model WN+RW` with `extra` options; the JSON and CSV asked for, so
// that a case that got through would write them.
std::vector<std::string> fleet(const std::string& manifest, std::vector<std::string> extra = {}) {
  std::vector<std::string> args = {"fleet", manifest, "--model", "WN+RW", "--json", "f.json", "--csv", "f.csv"};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

// The recording every manifest names, and a manifest `name` of `text`.
Setup manifest(const std::string& name, const std::string& text) {
  return both(file("base.csv", base_csv()), file(name, text));
}

// A good manifest of one row, for the cases whose fault is elsewhere.
const char* const kGood = "path,unit,model\nbase.csv,SN1,IMU-X\n";

std::vector<Case> corpus() {
  std::string utf16 = "\xFF\xFE";
  for (char c : std::string(kGood)) utf16 += std::string(1, c) + '\0';
  // Nine sequences of nine aliases, seven deep: 9^7 recordings if expanded.
  std::string bomb = "a: &a [x, x, x, x, x, x, x, x, x]\n";
  for (char c = 'b'; c <= 'g'; ++c) {
    const std::string name(1, c), prev(1, static_cast<char>(c - 1));
    bomb += name + ": &" + name + " [";
    for (int k = 0; k < 9; ++k) bomb += std::string(k ? ", *" : "*") + prev;
    bomb += "]\n";
  }
  bomb += "recordings: *g\n";
  const std::string spec_head = "IMU-X:\n  gyroscope:\n";
  return {
      // --- Encodings and bytes ------------------------------------------------------------
      {"manifest in UTF-16",
       fleet("m.csv"),
       {"m.csv:1: found UTF-16 text (its byte-order mark FF FE), expected UTF-8"},
       manifest("m.csv", utf16)},
      {"manifest with a NUL byte in a unit",
       fleet("m.csv"),
       {"m.csv:2: found a NUL byte, expected text"},
       manifest("m.csv", std::string("path,unit,model\nbase.csv,SN") + '\0' + "1,IMU-X\n")},
      {"manifest with CR-only line ends",
       fleet("m.csv"),
       {"m.csv:1: found carriage returns (CR) as line ends", "expected LF or CRLF"},
       manifest("m.csv", "path,unit,model\rbase.csv,SN1,IMU-X\r")},
      {"unit name that is not UTF-8",
       fleet("m.csv"),
       {"m.csv:2: unit: found bytes that are not UTF-8 in 'SN\\xFF1'", "nothing analysed"},
       manifest("m.csv",
                "path,unit,model\nbase.csv,SN\xFF"
                "1,IMU-X\n")},
      {"model name with a terminal escape",
       fleet("m.csv"),
       {"m.csv:2: model: found a control character in 'IMU\\x1B[2J'"},
       manifest("m.csv", "path,unit,model\nbase.csv,SN1,IMU\x1b[2J\n")},
      // --- Sizes ------------------------------------------------------------------------------
      {"unit field of two megabytes",
       fleet("m.csv"),
       {"m.csv:2: unit: found 2097152 bytes, expected at most 4096"},
       manifest("m.csv", "path,unit,model\nbase.csv," + std::string(2 << 20, 'u') + ",IMU-X\n")},
      {"yaml group longer than a path",
       fleet("m.yaml"),
       {"m.yaml:2: group: found 5000 bytes, expected at most 4096"},
       manifest("m.yaml",
                "recordings:\n  - {path: base.csv, unit: SN1, model: IMU-X, group: " + std::string(5000, 'g') + "}\n")},
      {"manifest beyond sixteen megabytes",
       fleet("m.csv"),
       {"m.csv: holds more than 16777216 bytes"},
       manifest("m.csv", std::string(kGood) + std::string(17 << 20, '#'))},
      {"yaml alias bomb",
       fleet("m.yaml"),
       {"m.yaml:", "expected a recording: a map with path, unit, model"},
       manifest("m.yaml", bomb)},
      // --- Rows ---------------------------------------------------------------------------
      {"unit given twice",
       fleet("m.csv"),
       {"m.csv:3: unit 'SN1' given twice (first at row 2)"},
       manifest("m.csv", "path,unit,model\nbase.csv,SN1,IMU-X\nbase.csv,SN1,IMU-Y\n")},
      {"path climbing out of the folder to a folder",
       fleet("m.csv"),
       {"m.csv:2: ", "is a folder, expected a data file"},
       manifest("m.csv", "path,unit,model\n../..,SN1,IMU-X\n")},
      {"path naming a device",
       fleet("m.csv"),
       {"m.csv:2: /dev/zero"},
       manifest("m.csv", "path,unit,model\n/dev/zero,SN1,IMU-X\n")},
      {"path to a recording that is not there",
       fleet("m.csv"),
       {"m.csv:2: ", "gone.csv: file not found"},
       manifest("m.csv", "path,unit,model\ngone.csv,SN1,IMU-X\n")},
      {"column the recording lacks",
       fleet("m.csv"),
       {"m.csv:2: ", "found no column named 'gyro_q'"},
       manifest("m.csv", "path,unit,model,columns\nbase.csv,SN1,IMU-X,gyro_q\n")},
      {"rate beyond a double",
       fleet("m.csv"),
       {"m.csv:2: rate: found '1e400', expected a sampling rate in Hz"},
       manifest("m.csv", "path,unit,model,rate\nbase.csv,SN1,IMU-X,1e400\n")},
      {"units of no sensor",
       fleet("m.csv"),
       {"m.csv:2: units: ", "furlong"},
       manifest("m.csv", "path,unit,model,units\nbase.csv,SN1,IMU-X,gyro=furlong\n")},
      // --- The file's shape -----------------------------------------------------------------
      {"unknown column in the header",
       fleet("m.csv"),
       {"m.csv:1: found the header field 'colour', expected some of path, unit, model"},
       manifest("m.csv", "path,unit,model,colour\nbase.csv,SN1,IMU-X,red\n")},
      {"header without the model",
       fleet("m.csv"),
       {"m.csv:1: found a header without 'model'"},
       manifest("m.csv", "path,unit\nbase.csv,SN1\n")},
      {"unterminated quoted field",
       fleet("m.csv"),
       {"m.csv:2: found an unterminated quoted field"},
       manifest("m.csv", "path,unit,model\nbase.csv,\"SN1,IMU-X\n")},
      {"row shorter than the header",
       fleet("m.csv"),
       {"m.csv:2: found 2 fields, expected 3"},
       manifest("m.csv", "path,unit,model\nbase.csv,SN1\n")},
      {"manifest without a recording",
       fleet("m.csv"),
       {"m.csv: found no recording"},
       manifest("m.csv", "path,unit,model\n# every unit left out\n")},
      {"yaml recording that is not a map",
       fleet("m.yaml"),
       {"m.yaml:2: expected a recording: a map"},
       manifest("m.yaml", "recordings:\n  - base.csv\n")},
      {"yaml recording with a key twice",
       fleet("m.yaml"),
       {"m.yaml:2: duplicate key 'unit'"},
       manifest("m.yaml", "recordings:\n  - {path: base.csv, unit: SN1, unit: SN2, model: IMU-X}\n")},
      {"manifest that is a device", fleet("/dev/zero"), {"/dev/zero: is a character device"}, nullptr},
      // --- The cache ----------------------------------------------------------------------
      {"default cache that is a file",
       fleet("m.csv"),
       {"the default cache .gmwm-cache: found a file, expected the folder", "--no-cache"},
       both(manifest("m.csv", kGood), file(".gmwm-cache", "my notes\n"))},
      {"cache below a file",
       fleet("m.csv", {"--cache", "notes.txt/cache"}),
       {"--cache notes.txt/cache's parent notes.txt: found a file"},
       both(manifest("m.csv", kGood), file("notes.txt", "mine\n"))},
      {"cache that is a link to nothing",
       fleet("m.csv", {"--cache", "link"}),
       {"--cache link: found a link to nothing"},
       both(manifest("m.csv", kGood), [](const fs::path& d) { fs::create_symlink(d / "gone", d / "link"); })},
      {"cache that is a device",
       fleet("m.csv", {"--cache", "/dev/null"}),
       {"--cache /dev/null: found a special file"},
       manifest("m.csv", kGood)},
      // --- Spec and baseline files ----------------------------------------------------------
      {"spec limit in the unit of another figure",
       fleet("m.csv", {"--spec", "s.yaml"}),
       {"s.yaml:3: gyroscope.angle_random_walk: 'deg/h' is not a unit of a angle random walk"},
       both(manifest("m.csv", kGood), file("s.yaml", spec_head + "    angle_random_walk: 5 deg/h\n"))},
      {"spec that is not yaml",
       fleet("m.csv", {"--spec", "s.yaml"}),
       {"s.yaml:2:1: not valid YAML"},
       both(manifest("m.csv", kGood), file("s.yaml", "IMU-X: [unclosed\n"))},
      {"spec with a figure twice",
       fleet("m.csv", {"--spec", "s.yaml"}),
       {"s.yaml:4: duplicate key 'angle_random_walk'"},
       both(manifest("m.csv", kGood), file("s.yaml", spec_head + "    angle_random_walk: 5 deg/sqrt(h)\n" +
                                                         "    angle_random_walk: 6 deg/sqrt(h)\n"))},
      {"spec with a negative limit",
       fleet("m.csv", {"--spec", "s.yaml"}),
       {"s.yaml:3: gyroscope.angle_random_walk: found -5, expected a non-negative figure"},
       both(manifest("m.csv", kGood), file("s.yaml", spec_head + "    angle_random_walk: -5 deg/sqrt(h)\n"))},
      {"spec beyond a megabyte",
       fleet("m.csv", {"--spec", "s.yaml"}),
       {"s.yaml: holds more than 1048576 bytes"},
       both(manifest("m.csv", kGood),
            file("s.yaml", spec_head + "    angle_random_walk: 5 deg/sqrt(h)\n#" + std::string(2 << 20, 'x') + "\n"))},
      {"gap baseline that is not yaml",
       fleet("m.csv", {"--gap-datasheet", "g.yaml"}),
       {"--gap-datasheet g.yaml:2:1: not valid YAML"},
       both(manifest("m.csv", kGood), file("g.yaml", "gyroscope: [unclosed\n"))},
      // --- Outputs over the inputs ----------------------------------------------------------
      {"table over the manifest",
       {"fleet", "m.csv", "--model", "WN+RW", "--csv", "m.csv"},
       {"--csv 'm.csv': is the input 'm.csv'"},
       manifest("m.csv", kGood)},
      {"json over a recording",
       {"fleet", "m.csv", "--model", "WN+RW", "--json", "base.csv"},
       {"--json 'base.csv': is the input 'base.csv'"},
       manifest("m.csv", kGood)},
  };
}

}  // namespace

HOSTILE_CORPUS(HostileFleet, corpus());
