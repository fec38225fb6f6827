// What reaches an answer is UTF-8 (shell/utf8_text.h): RFC 3629's check, with the forms a looser
// check let through (surrogates, overlong forms, code points past U+10FFFF), and the answers'
// one writer, which replaces what is not UTF-8 rather than throwing.
#include "shell/utf8_text.h"
#include "watch/diagnostic.h"

#include <gtest/gtest.h>

namespace dw::shell {
namespace {

TEST(Utf8Text, EveryFormOfUtf8IsAccepted) {
  EXPECT_EQ(watch::first_non_utf8(""), std::nullopt);
  EXPECT_EQ(watch::first_non_utf8("plain ascii\t\n"), std::nullopt);
  EXPECT_EQ(watch::first_non_utf8("caf\xC3\xA9 \xE2\x80\xA6 \xF0\x9F\x98\x80"), std::nullopt);  // é … 😀
  EXPECT_EQ(watch::first_non_utf8("\xC2\x80 \xDF\xBF"), std::nullopt);                          // U+0080, U+07FF
  EXPECT_EQ(watch::first_non_utf8("\xE0\xA0\x80 \xED\x9F\xBF \xEE\x80\x80 \xEF\xBF\xBF"), std::nullopt);
  EXPECT_EQ(watch::first_non_utf8("\xF0\x90\x80\x80 \xF4\x8F\xBF\xBF"), std::nullopt);  // U+10000, U+10FFFF
}

TEST(Utf8Text, SurrogatesOverlongFormsAndCodePointsPastTheLastAreRefused) {
  EXPECT_EQ(watch::first_non_utf8("\xED\xA0\x80"), 0u);       // U+D800, a surrogate
  EXPECT_EQ(watch::first_non_utf8("ab\xED\xBF\xBF"), 2u);     // U+DFFF
  EXPECT_EQ(watch::first_non_utf8("\xE0\x80\xAF"), 0u);       // '/' in three bytes
  EXPECT_EQ(watch::first_non_utf8("\xE0\x9F\xBF"), 0u);       // U+07FF in three bytes
  EXPECT_EQ(watch::first_non_utf8("\xF0\x80\x80\xAF"), 0u);   // '/' in four bytes
  EXPECT_EQ(watch::first_non_utf8("\xF0\x8F\xBF\xBF"), 0u);   // U+FFFF in four bytes
  EXPECT_EQ(watch::first_non_utf8("x\xF4\x90\x80\x80"), 1u);  // U+110000
  EXPECT_EQ(watch::first_non_utf8("\xF5\x80\x80\x80"), 0u);   // no lead byte past F4
  EXPECT_EQ(watch::first_non_utf8("\xC0\xAF"), 0u);           // an overlong two-byte lead
  EXPECT_EQ(watch::first_non_utf8("\xC1\xBF"), 0u);
  EXPECT_EQ(watch::first_non_utf8("ab\xFF"), 2u);
  EXPECT_EQ(watch::first_non_utf8("a\xC3"), 1u);  // cut short
  EXPECT_EQ(watch::first_non_utf8("\xE2\x82"), 0u);
  EXPECT_EQ(watch::first_non_utf8("\x80x"), 0u);             // a stray continuation byte
  EXPECT_EQ(watch::first_non_utf8("\xE2\x28\xA1"), 0u);      // a lead whose next byte is no continuation
  EXPECT_EQ(watch::first_non_utf8("\xF0\x9F\x98\x28"), 0u);  // nor its last
}

TEST(Utf8Text, WhatIsNotUtf8IsReplacedOneCharacterAByte) {
  EXPECT_EQ(replace_invalid_utf8("ok \xC3\xA9"), "ok \xC3\xA9");
  EXPECT_EQ(replace_invalid_utf8("a\xFF"
                                 "b"),
            "a\xEF\xBF\xBD"
            "b");
  EXPECT_EQ(replace_invalid_utf8("\xED\xA0\x80"), "\xEF\xBF\xBD\xEF\xBF\xBD\xEF\xBF\xBD");
  EXPECT_EQ(watch::first_non_utf8(replace_invalid_utf8("\xF4\x90\x80\x80 \xE0\x80\xAF \xC3")), std::nullopt);
}

TEST(Utf8Text, AnAnswerHoldingBytesThatAreNotUtf8IsWrittenNotThrown) {
  const nlohmann::ordered_json answer = {{"error", {{"message", "bad \xFF \xED\xA0\x80 end"}}}, {"t", 3}};
  std::string line;
  ASSERT_NO_THROW(line = answer_line(answer));
  EXPECT_EQ(watch::first_non_utf8(line), std::nullopt) << line;
  EXPECT_EQ(nlohmann::json::parse(line)["t"], 3);
  EXPECT_EQ(answer_line({{"name", "caf\xC3\xA9"}}), "{\"name\":\"caf\xC3\xA9\"}");
}

}  // namespace
}  // namespace dw::shell
