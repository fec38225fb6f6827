#include "watch/diagnostic.h"

#include <gtest/gtest.h>

namespace dw::watch {
namespace {

TEST(Diagnostic, LocationLineAndCaretUnderTheSpan) {
  SourceText src("w.txt", "modules(a);\n  (a.x = 1) and (b.y = 2)\n");
  const uint32_t at = static_cast<uint32_t>(src.text().find("b.y"));
  const std::string out = format_diagnostic(src, {{at, at + 3}, "module 'b' is not declared"});
  EXPECT_EQ(out,
            "w.txt:2:18: error: module 'b' is not declared\n"
            "  (a.x = 1) and (b.y = 2)\n"
            "                 ^~~\n");
}

TEST(Diagnostic, TabsAreKeptSoTheCaretLinesUp) {
  SourceText src("w", "\tx");
  EXPECT_EQ(format_diagnostic(src, {{1, 2}, "m"}), "w:1:2: error: m\n\tx\n\t^\n");
}

TEST(Diagnostic, AtEndOfInputPointsPastTheLastCharacter) {
  SourceText src("w", "modules(a");
  EXPECT_EQ(format_diagnostic(src, {{9, 9}, "expected ')'"}), "w:1:10: error: expected ')'\nmodules(a\n         ^\n");
}

TEST(Diagnostic, SpanPastTheLineIsClipped) {
  SourceText src("w", "ab\ncd");
  EXPECT_EQ(format_diagnostic(src, {{0, 5}, "m"}), "w:1:1: error: m\nab\n^~\n");
}

}  // namespace
}  // namespace dw::watch
