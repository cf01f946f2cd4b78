// What reaches a terminal or a message (error.h).
#include <gtest/gtest.h>

#include <string>

#include "gmwm/engine/error.h"

namespace gmwm {
namespace {

TEST(PrintableText, KeepsLineBreaksTabsAndUtf8AndShowsEveryOtherControlAsHex) {
  EXPECT_EQ(printable_text("a\tb\nc \xC3\xA9\n"), "a\tb\nc \xC3\xA9\n");
  EXPECT_EQ(printable_text("x\x1b[2Jy"), "x\\x1B[2Jy");
  EXPECT_EQ(printable_text("over\rwrite"), "over\\x0Dwrite");
  EXPECT_EQ(printable_text("bell\x07"), "bell\\x07");
  EXPECT_EQ(printable_text("del\x7f"), "del\\x7F");
  // C1 controls are valid UTF-8 but act as escapes (U+009B is CSI): shown as bytes.
  EXPECT_EQ(printable_text("c1\xC2\x9B" "31m"), "c1\\xC2\\x9B31m");
  EXPECT_EQ(printable_text("nbsp\xC2\xA0ok"), "nbsp\xC2\xA0ok");
  EXPECT_EQ(printable_text(std::string("nul\0x", 5)), "nul\\x00x");
  EXPECT_EQ(printable_text("bad\xFF"), "bad\\xFF");
}

TEST(PrintableLine, IsOneLineWithTheSameEscapes) {
  EXPECT_EQ(printable_line("a\nb\r\nc\x1b "), "a b  c\\x1B");
  EXPECT_EQ(printable_line("\xC2\x85next line"), "\\xC2\\x85next line");
}

}  // namespace
}  // namespace gmwm
