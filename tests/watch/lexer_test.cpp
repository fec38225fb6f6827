#include "watch/lexer.h"

#include <gtest/gtest.h>

namespace dw::watch {
namespace {

std::vector<Token> tokens(const std::string& text) { return lex(SourceText("t", text)); }

TEST(Lexer, KeywordsNamesAndPunctuation) {
  auto t = tokens("modules(a b);not and or neighbor last next x1 _y");
  std::vector<TokenKind> kinds;
  for (const Token& tok : t) kinds.push_back(tok.kind);
  EXPECT_EQ(kinds, (std::vector<TokenKind>{TokenKind::Modules, TokenKind::LParen, TokenKind::Name, TokenKind::Name,
                                           TokenKind::RParen, TokenKind::Semicolon, TokenKind::Not, TokenKind::And,
                                           TokenKind::Or, TokenKind::Neighbor, TokenKind::Last, TokenKind::Next,
                                           TokenKind::Name, TokenKind::Name, TokenKind::End}));
}

TEST(Lexer, AllComparisonOperators) {
  auto t = tokens("< > = != >= <=");
  ASSERT_EQ(t.size(), 7u);
  EXPECT_EQ(t[0].kind, TokenKind::Less);
  EXPECT_EQ(t[1].kind, TokenKind::Greater);
  EXPECT_EQ(t[2].kind, TokenKind::Equal);
  EXPECT_EQ(t[3].kind, TokenKind::NotEqual);
  EXPECT_EQ(t[4].kind, TokenKind::GreaterEqual);
  EXPECT_EQ(t[5].kind, TokenKind::LessEqual);
}

TEST(Lexer, IntegersIncludingExtremes) {
  auto t = tokens("0 42 -7 9223372036854775807 -9223372036854775808");
  EXPECT_EQ(t[0].value, 0);
  EXPECT_EQ(t[1].value, 42);
  EXPECT_EQ(t[2].value, -7);
  EXPECT_EQ(t[3].value, INT64_MAX);
  EXPECT_FALSE(t[3].overflow);
  EXPECT_EQ(t[4].value, INT64_MIN);
  EXPECT_FALSE(t[4].overflow);
}

TEST(Lexer, IntegerOverflowIsFlagged) {
  auto t = tokens("9223372036854775808 -9223372036854775809 123456789012345678901234567890");
  EXPECT_TRUE(t[0].overflow);
  EXPECT_TRUE(t[1].overflow);
  EXPECT_TRUE(t[2].overflow);
}

TEST(Lexer, NonIntegersAreTheirOwnKind) {
  auto t = tokens("1.5 2e3 -0.25");
  EXPECT_EQ(t[0].kind, TokenKind::NonInteger);
  EXPECT_EQ(t[1].kind, TokenKind::NonInteger);
  EXPECT_EQ(t[2].kind, TokenKind::NonInteger);
}

TEST(Lexer, CommentsRunToEndOfLine) {
  auto t = tokens("# a comment ( ) and\nmodules # another\n(");
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(t[0].kind, TokenKind::Modules);
  EXPECT_EQ(t[1].kind, TokenKind::LParen);
}

TEST(Lexer, SpansCoverTheToken) {
  auto t = tokens("  abc != 12");
  EXPECT_EQ(t[0].span.begin, 2u);
  EXPECT_EQ(t[0].span.end, 5u);
  EXPECT_EQ(t[1].span.begin, 6u);
  EXPECT_EQ(t[1].span.end, 8u);
  EXPECT_EQ(t[2].span.begin, 9u);
  EXPECT_EQ(t[2].span.end, 11u);
}

TEST(Lexer, InvalidCharactersExplainThemselves) {
  auto t = tokens("a == b");
  EXPECT_EQ(t[1].kind, TokenKind::Invalid);
  EXPECT_NE(t[1].message.find("equality is '='"), std::string::npos);
  t = tokens("! $ 1abc");
  EXPECT_EQ(t[0].kind, TokenKind::Invalid);
  EXPECT_EQ(t[1].kind, TokenKind::Invalid);
  EXPECT_NE(t[1].message.find("'$'"), std::string::npos);
  EXPECT_EQ(t[2].kind, TokenKind::Invalid);
  EXPECT_NE(t[2].message.find("malformed number"), std::string::npos);
}

TEST(Lexer, MinusWithoutDigitIsInvalid) {
  auto t = tokens("a - 1");
  EXPECT_EQ(t[1].kind, TokenKind::Invalid);
}

}  // namespace
}  // namespace dw::watch
