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

TEST(Lexer, IntegersAreMagnitudesAndMinusIsAnOperator) {
  auto t = tokens("0 42 -7 9223372036854775807 9223372036854775808");
  EXPECT_EQ(t[0].value, 0u);
  EXPECT_EQ(t[1].value, 42u);
  EXPECT_EQ(t[2].kind, TokenKind::Minus);
  EXPECT_EQ(t[3].value, 7u);
  EXPECT_EQ(t[4].value, static_cast<uint64_t>(INT64_MAX));
  EXPECT_FALSE(t[4].overflow);
  EXPECT_EQ(t[5].value, uint64_t{1} << 63);  // -9223372036854775808's magnitude
  EXPECT_FALSE(t[5].overflow);
}

TEST(Lexer, IntegerOverflowIsFlagged) {
  auto t = tokens("9223372036854775809 123456789012345678901234567890");
  EXPECT_TRUE(t[0].overflow);
  EXPECT_TRUE(t[1].overflow);
}

TEST(Lexer, NonIntegersAreTheirOwnKind) {
  auto t = tokens("1.5 2e3 -0.25");
  EXPECT_EQ(t[0].kind, TokenKind::NonInteger);
  EXPECT_EQ(t[1].kind, TokenKind::NonInteger);
  EXPECT_EQ(t[2].kind, TokenKind::Minus);
  EXPECT_EQ(t[3].kind, TokenKind::NonInteger);
}

TEST(Lexer, ArithmeticAndTheKeywordsOfExpressions) {
  auto t = tokens("+ - * / % : in neighbors count sum min max abs then set remove");
  const std::vector<TokenKind> want = {
      TokenKind::Plus, TokenKind::Minus,     TokenKind::Star,  TokenKind::Slash,  TokenKind::Percent, TokenKind::Colon,
      TokenKind::In,   TokenKind::Neighbors, TokenKind::Count, TokenKind::Sum,    TokenKind::Min,     TokenKind::Max,
      TokenKind::Abs,  TokenKind::Then,      TokenKind::Set,   TokenKind::Remove, TokenKind::End};
  ASSERT_EQ(t.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i) EXPECT_EQ(t[i].kind, want[i]) << i;
  EXPECT_TRUE(is_keyword(TokenKind::Count));
  EXPECT_FALSE(is_reserved(TokenKind::Count));  // `a.count` names a variable
  EXPECT_TRUE(is_reserved(TokenKind::Neighbor));
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

// A comparison typed as one mathematical sign is named with its ASCII spelling, its span the
// whole character (three bytes of UTF-8).
TEST(Lexer, MathematicalComparisonSignsSuggestTheirSpelling) {
  const auto t = tokens("a \u2265 b \u2264 c \u2260 d");
  ASSERT_EQ(t.size(), 8u);
  for (const auto& [i, spelling] : {std::pair{1, "'>='"}, std::pair{3, "'<='"}, std::pair{5, "'!='"}}) {
    EXPECT_EQ(t[i].kind, TokenKind::Invalid);
    EXPECT_NE(t[i].message.find("use " + std::string(spelling)), std::string::npos) << t[i].message;
    EXPECT_EQ(t[i].span.length(), 3u);
  }
}

}  // namespace
}  // namespace dw::watch
