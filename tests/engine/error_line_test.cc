// gmwm::capped_line (error.h): an error line of at most kMaxErrorLineBytes and its note,
// quoted text shortened first, the end of the sentence kept, no character or \xNN escape cut.
#include <gtest/gtest.h>

#include <string>

#include "gmwm/engine/error.h"

namespace gmwm {
namespace {

constexpr std::size_t kNote = 32;  // "...[N more bytes]" at most

TEST(ErrorLine, AShortLineIsUnchanged) {
  EXPECT_EQ(capped_line("f.csv:3:2: found 'x', expected a number"), "f.csv:3:2: found 'x', expected a number");
}

TEST(ErrorLine, ShortensTheQuotedTextAndKeepsTheSentencesEnd) {
  const std::string line = "f.csv:3:2: found '" + std::string(10'000'000, 'z') + "', expected a number";
  const std::string out = capped_line(line);
  EXPECT_LE(out.size(), kMaxErrorLineBytes + kNote);
  EXPECT_EQ(out.rfind("f.csv:3:2: found 'zzzz", 0), 0u) << out;
  EXPECT_NE(out.find("...["), std::string::npos);
  EXPECT_NE(out.find(" more bytes]', expected a number"), std::string::npos) << out;
}

TEST(ErrorLine, CutsTheMiddleOfALineWithoutQuotes) {
  const std::string line = "head " + std::string(5000, 'm') + " expected the end";
  const std::string out = capped_line(line);
  EXPECT_LE(out.size(), kMaxErrorLineBytes + kNote);
  EXPECT_EQ(out.rfind("head ", 0), 0u);
  EXPECT_EQ(out.substr(out.size() - 17), " expected the end");
}

TEST(ErrorLine, NeverSplitsAUtf8CharacterOrAnEscape) {
  std::string text;
  for (int i = 0; i < 2000; ++i) text += i % 2 ? "\xC3\xA9" : "\\x01";  // é and an escape
  const std::string out = capped_line("found '" + text + "', expected text");
  const std::string printable = printable_line(out);
  EXPECT_EQ(printable, out) << "a cut left a broken UTF-8 sequence";
  const auto head = out.substr(0, out.find("...["));
  EXPECT_TRUE(head.size() < 3 || head.substr(head.size() - 2) == "\xC3\xA9" || head.substr(head.size() - 4, 2) == "\\x")
      << head.substr(head.size() - 6);
}

TEST(ErrorLine, AnInputErrorIsCapped) {
  const InputError e("--model '" + std::string(100000, 'Q') + "': unknown process");
  EXPECT_LE(std::string(e.what()).size(), kMaxErrorLineBytes + kNote);
  EXPECT_NE(std::string(e.what()).find("': unknown process"), std::string::npos);
}

}  // namespace
}  // namespace gmwm
