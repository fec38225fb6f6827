// app/cli/terminal_filter.cpp: what an input put in a message reaches a terminal as text.
#include "app/cli/terminal_filter.h"

#include <gtest/gtest.h>

#include <sstream>

namespace dw::app {
namespace {

std::string filtered(std::initializer_list<std::string> writes) {
  std::ostringstream sink;
  TerminalFilter filter(sink.rdbuf());
  std::ostream out(&filter);
  for (const std::string& w : writes) out << w;
  out.flush();
  return sink.str();
}

TEST(TerminalFilter, ControlCharactersBecomeQuestionMarksAndTextStays) {
  // ESC [2J (clear the screen), a bell, DEL and U+009B (CSI in one character) are shown one '?'
  // a byte; tab, newline, carriage return and other UTF-8 (U+00A9, U+00E9, U+2026) are kept.
  EXPECT_EQ(filtered({"a\x1b[2J\x07\x7f\xc2\x9b"
                      "1m\xc2\xa9\xc3\xa9\xe2\x80\xa6\t\r\n"}),
            "a?[2J????1m\xc2\xa9\xc3\xa9\xe2\x80\xa6\t\r\n");
}

TEST(TerminalFilter, AC1ControlSplitAcrossWritesIsStillCaught) {
  EXPECT_EQ(filtered({"x\xc2", "\x85y"}), "x??y");
  EXPECT_EQ(filtered({"x\xc2", "\xa9"}), "x\xc2\xa9");
  EXPECT_EQ(filtered({"end\xc2"}), "end\xc2") << "held back, then written at the flush";
}

}  // namespace
}  // namespace dw::app
