// The bad-input contract (hostile_harness.h) for what issue 25 found beyond reading a
// file: standard output closed under the writer (a pipe to `head -c1`).
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "hostile_harness.h"

namespace fs = std::filesystem;
using namespace gmwm::test::hostile;
using gmwm::test::RunOptions;

namespace {

// A CSV of `columns` signals of 1024 rows at 100 Hz: its wv JSON (about 2.5 kB a column)
// and its table are far beyond a pipe's 64 KiB, so a reader that stops after one byte
// makes the writer meet a closed pipe whatever the scheduling.
std::string wide_csv(int columns) {
  std::string s = "time";
  for (int c = 0; c < columns; ++c) s += ",g" + std::to_string(c);
  s += "\n";
  for (int i = 0; i < 1024; ++i) {
    s += std::to_string(i * 0.01);
    for (int c = 0; c < columns; ++c) s += "," + std::to_string(std::sin(i * 0.37 + c) * 1e-3 + c);
    s += "\n";
  }
  return s;
}

// Standard output into a reader that takes one byte and exits.
RunOptions to_head() {
  RunOptions how;
  how.stdout_to = ">(head -c1 >/dev/null)";
  return how;
}

std::vector<Case> corpus() {
  const auto wide = file("wide.csv", wide_csv(200));
  std::vector<Case> c = {
      // --- standard output closed under the writer -------------------------------------------
      {"json on a closed pipe with a csv beside it", {"wv", "wide.csv", "--json", "-", "--csv", "out.csv"},
       {"--json -: cannot write to standard output: Broken pipe", "no output file was written"}, wide, to_head()},
      {"fit json on a closed pipe",
       {"fit", "wide.csv", "--model", "WN", "--json", "-", "--quiet"}, {"--json -", "Broken pipe"}, wide, to_head()},
      {"simulated series on a closed pipe", {"simulate", "--model", "WN(sigma2=1)", "--n", "200000", "--output", "-",
                                             "--json", "s.json"},
       {"--output -: cannot write to standard output: Broken pipe"}, nullptr, to_head()},
      {"table on a closed pipe", {"wv", "wide.csv"}, {"cannot write to standard output: Broken pipe"}, wide, to_head()},
  };
  return c;
}

}  // namespace

HOSTILE_CORPUS(HostileOutputs, corpus());
