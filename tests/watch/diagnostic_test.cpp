#include "watch/diagnostic.h"

#include <gtest/gtest.h>

#include <sstream>

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

TEST(Diagnostic, BytesATerminalWouldActOnAreShownAsQuestionMarks) {
  // An escape sequence, a bell and bytes that are not UTF-8 (a binary file given as a scenario):
  // one '?' each, so that the caret stays under its column; valid UTF-8 stays.
  SourceText src("w", std::string("a\x1b[2J\x07\xff\xfe \xc3\xa9 x"));
  const uint32_t at = static_cast<uint32_t>(src.text().find(" x") + 1);
  EXPECT_EQ(format_diagnostic(src, {{at, at + 1}, "m"}),
            "w:1:" + std::to_string(at + 1) + ": error: m\na?[2J??? \xc3\xa9 x\n           ^\n");
}

TEST(Diagnostic, C1ControlCharactersAreShownAsQuestionMarks) {
  // U+009B is a terminal's one-character CSI (as ESC [): "\xc2\x9b" "2J" would clear the screen.
  // Both its bytes become '?', so the caret keeps its column; U+00A0 (no control) stays.
  SourceText src("w", std::string("\xc2\x9b"
                                  "2J\xc2\x85\xc2\xa0 x"));
  const uint32_t at = static_cast<uint32_t>(src.text().find(" x") + 1);
  EXPECT_EQ(format_diagnostic(src, {{at, at + 1}, "m"}),
            "w:1:" + std::to_string(at + 1) + ": error: m\n??2J??\xc2\xa0 x\n        ^\n");
}

TEST(Diagnostic, AtEndOfInputPointsPastTheLastCharacter) {
  SourceText src("w", "modules(a");
  EXPECT_EQ(format_diagnostic(src, {{9, 9}, "expected ')'"}), "w:1:10: error: expected ')'\nmodules(a\n         ^\n");
}

TEST(Diagnostic, SpanPastTheLineIsClipped) {
  SourceText src("w", "ab\ncd");
  EXPECT_EQ(format_diagnostic(src, {{0, 5}, "m"}), "w:1:1: error: m\nab\n^~\n");
}

TEST(Diagnostic, ALongLineIsShownAsAWindowAroundTheCaret) {
  const std::string text = "modules(a); " + std::string(1'000'000, '(');
  SourceText src("w", text);
  const uint32_t at = 500'000;
  const std::string out = format_diagnostic(src, {{at, at + 1}, "m"});
  EXPECT_LT(out.size(), 400u) << "not the whole megabyte";
  std::istringstream lines(out);
  std::string header, shown, caret;
  std::getline(lines, header);
  std::getline(lines, shown);
  std::getline(lines, caret);
  EXPECT_EQ(header, "w:1:500001: error: m");
  EXPECT_EQ(shown.substr(0, 3), "...");
  EXPECT_EQ(shown.substr(shown.size() - 3), "...");
  EXPECT_LE(shown.size(), kShownColumns + 6);
  EXPECT_EQ(caret.size(), caret.find('^') + 1);
  EXPECT_EQ(shown[caret.find('^')], '(') << "the caret under the character";
  // A line just short enough is shown whole; the start of a long one without a leading "...".
  SourceText start("w", std::string(1000, 'x'));
  const std::string first = format_diagnostic(start, {{2, 3}, "m"});
  EXPECT_EQ(first.find("\nxx^"), std::string::npos);
  EXPECT_NE(first.find("\n  ^\n"), std::string::npos) << first;
  EXPECT_NE(first.find(std::string(kShownColumns, 'x') + "...\n"), std::string::npos);
}

TEST(Diagnostic, TheWindowNeverSplitsAUtf8Character) {
  std::string text;
  for (int i = 0; i < 400; ++i) text += "\xC3\xA9";  // é
  SourceText src("w", text);
  const std::string out = format_diagnostic(src, {{401, 402}, "m"});
  const std::string shown = out.substr(out.find('\n') + 1, out.find('\n', out.find('\n') + 1) - out.find('\n') - 1);
  const std::string inner = shown.substr(3, shown.size() - 6);
  EXPECT_EQ(inner.size() % 2, 0u) << "whole two-byte characters only";
  EXPECT_EQ(uint8_t(inner[0]), 0xC3u);
}

}  // namespace
}  // namespace dw::watch

namespace dw::watch {
namespace {

TEST(FirstNonUtf8, FindsTheFirstByteNoCharacterStartsAt) {
  EXPECT_EQ(first_non_utf8("plain ascii"), std::nullopt);
  EXPECT_EQ(first_non_utf8("caf\xC3\xA9 \xE2\x80\xA6 \xF0\x9F\x98\x80"), std::nullopt);  // é … 😀
  EXPECT_EQ(first_non_utf8("ab\xFF"), 2u);
  EXPECT_EQ(first_non_utf8("a\xC3"), 1u);         // cut short
  EXPECT_EQ(first_non_utf8("\x80x"), 0u);         // a stray continuation byte
  EXPECT_EQ(first_non_utf8("x\xC0\xAF"), 1u);     // an overlong lead
  EXPECT_EQ(first_non_utf8("\xE2\x28\xA1"), 0u);  // a lead whose next byte is no continuation
}

}  // namespace
}  // namespace dw::watch
