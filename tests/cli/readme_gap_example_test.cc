// The README's gap example is what the command prints today: the fenced block that starts
// with "$ build/gmwm gap" is run (from the source root, as the README says) and its
// headline compared with the command's summary line for that column.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "test_support.h"

namespace {

struct Example {
  std::vector<std::string> args;  ///< after "build/gmwm"
  std::string headline;           ///< the block's lines after the command, joined by spaces
};

// The first fenced block of README.md whose first line is "$ build/gmwm gap ...".
Example readme_gap_example() {
  const std::string text = gmwm::test::read_text(std::filesystem::path(GMWM_SOURCE_DIR) / "README.md");
  std::istringstream is(text);
  Example ex;
  bool in_block = false, found = false;
  for (std::string line; std::getline(is, line);) {
    if (!in_block) {
      if (line == "```") in_block = true;
      continue;
    }
    if (line == "```") {
      if (found) break;
      in_block = false;
      continue;
    }
    if (!found) {
      if (line.rfind("$ build/gmwm gap ", 0) != 0) {
        in_block = false;  // another block: skip to its end
        while (std::getline(is, line) && line != "```") {
        }
        continue;
      }
      found = true;
      std::istringstream words(line.substr(std::string("$ build/gmwm ").size()));
      for (std::string w; words >> w;) ex.args.push_back(w);
      continue;
    }
    ex.headline += (ex.headline.empty() ? "" : "\n") + line;
  }
  return ex;
}

TEST(ReadmeGapExample, PrintsTheHeadlineTheReadmeShows) {
  const Example ex = readme_gap_example();
  ASSERT_FALSE(ex.args.empty()) << "README.md has no block starting with '$ build/gmwm gap'";
  ASSERT_FALSE(ex.headline.empty());
  const auto r = gmwm::test::run_gmwm(ex.args, std::filesystem::path(GMWM_SOURCE_DIR));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The column's headline line (the first line that starts with the column's name and a colon).
  const std::string column = ex.headline.substr(0, ex.headline.find(':') + 1);
  // It wraps at the terminal's width: its continuation lines are indented 4 (items under it, 2).
  std::istringstream out(r.out);
  std::string printed;
  for (std::string line; std::getline(out, line);) {
    if (printed.empty() && line.rfind(column, 0) == 0) {
      printed = line;
    } else if (!printed.empty()) {
      if (line.rfind("    ", 0) != 0) break;
      printed += "\n" + line;
    }
  }
  EXPECT_EQ(printed, ex.headline) << "update README.md's gap example to what the command prints";
}

}  // namespace
