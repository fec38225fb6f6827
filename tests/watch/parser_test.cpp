#include "watch/parser.h"

#include <gtest/gtest.h>

namespace dw::watch {
namespace {

ParseResult p(const std::string& text) { return parse(SourceText("t", text)); }

TEST(Parser, Figure2) {
  auto r = p("modules(a b c);(a.isLeader = 1) and (c.isLeader = 1)");
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r.ast.slots.size(), 3u);
  EXPECT_EQ(r.ast.slots[2].name, "c");
  const Node& root = r.ast.nodes[r.ast.root];
  ASSERT_EQ(root.kind, NodeKind::And);
  const Node& right = r.ast.nodes[root.rhs];
  ASSERT_EQ(right.kind, NodeKind::Compare);
  const Node& var = r.ast.nodes[right.lhs];
  ASSERT_EQ(var.kind, NodeKind::Variable);
  EXPECT_EQ(var.x.slot, 2);
  EXPECT_EQ(var.name, "isLeader");
  const Node& one = r.ast.nodes[right.rhs];
  ASSERT_EQ(one.kind, NodeKind::Integer);
  EXPECT_EQ(one.value, 1);
}

TEST(Parser, AndBindsTighterThanOr) {
  auto r = p("modules(a); (a.x = 1) or (a.x = 2) and (a.x = 3)");
  ASSERT_TRUE(r.ok());
  const Node& root = r.ast.nodes[r.ast.root];
  EXPECT_EQ(root.kind, NodeKind::Or);
  EXPECT_EQ(r.ast.nodes[root.rhs].kind, NodeKind::And);
}

TEST(Parser, NotBindsTighterThanAnd) {
  auto r = p("modules(a); not (a.x = 1) and (a.x = 2)");
  ASSERT_TRUE(r.ok());
  const Node& root = r.ast.nodes[r.ast.root];
  EXPECT_EQ(root.kind, NodeKind::And);
  EXPECT_EQ(r.ast.nodes[root.lhs].kind, NodeKind::Not);
}

TEST(Parser, ChainsAreLeftAssociative) {
  auto r = p("modules(a); (a.x = 1) and (a.x = 2) and (a.x = 3)");
  ASSERT_TRUE(r.ok());
  const Node& root = r.ast.nodes[r.ast.root];
  EXPECT_EQ(r.ast.nodes[root.lhs].kind, NodeKind::And);
  EXPECT_EQ(r.ast.nodes[root.rhs].kind, NodeKind::Compare);
}

TEST(Parser, OffsetsCountNextAsPlusAndLastAsMinus) {
  auto r = p("modules(a b); (a.last.next.last.v = b.next.next.w) and neighbor(a.last b.last)");
  ASSERT_TRUE(r.ok());
  const Node& cmp = r.ast.nodes[r.ast.nodes[r.ast.root].lhs];
  EXPECT_EQ(r.ast.nodes[cmp.lhs].x.offset, -1);
  EXPECT_EQ(r.ast.nodes[cmp.lhs].name, "v");
  EXPECT_EQ(r.ast.nodes[cmp.rhs].x.offset, 2);
  const Node& nb = r.ast.nodes[r.ast.nodes[r.ast.root].rhs];
  EXPECT_EQ(nb.kind, NodeKind::Neighbor);
  EXPECT_EQ(nb.x.offset, -1);
  EXPECT_EQ(nb.y.slot, 1);
}

TEST(Parser, NegativeConstantsAndAllOperators) {
  auto r = p("modules(a); a.x < -1 and a.x > -2 and a.x = 0 and a.x != 3 and a.x >= 4 and a.x <= -5");
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(to_string(r.ast),
            "modules(a); (a.x < -1) and (a.x > -2) and (a.x = 0) and (a.x != 3) and (a.x >= 4) and (a.x <= -5)");
}

TEST(Parser, EverySpanCoversItsSource) {
  SourceText src("t", "modules(a b); ( a.x = b.last.y ) or neighbor(a b)");
  auto r = parse(src);
  ASSERT_TRUE(r.ok());
  const Node& root = r.ast.nodes[r.ast.root];
  EXPECT_EQ(src.slice(root.span), "( a.x = b.last.y ) or neighbor(a b)");
  const Node& cmp = r.ast.nodes[root.lhs];
  EXPECT_EQ(src.slice(r.ast.nodes[cmp.lhs].span), "a.x");
  EXPECT_EQ(src.slice(r.ast.nodes[cmp.rhs].span), "b.last.y");
  EXPECT_EQ(src.slice(r.ast.nodes[cmp.rhs].x.span), "b.last");
  EXPECT_EQ(src.slice(r.ast.nodes[root.rhs].span), "neighbor(a b)");
}

TEST(Parser, DeepNestingIsACleanErrorNotACrash) {
  const int depth = 100000;
  std::string text = "modules(a); " + std::string(depth, '(') + "a.x = 1" + std::string(depth, ')');
  auto r = p(text);
  ASSERT_EQ(r.diagnostics.size(), 1u);
  EXPECT_NE(r.diagnostics[0].message.find("nested too deeply"), std::string::npos);
}

// Past the limit the rest of the input is not read: each group open skipped to its ')' over all
// of it, so 4 MB of unclosed '(' took 35 s (minutes under the sanitizers) to give this one error.
TEST(Parser, DeepNestingLeavesTheRestUnread) {
  auto r = p("modules(a); " + std::string(4'000'000, '(') + "a.x = 1");
  ASSERT_EQ(r.diagnostics.size(), 1u);
  EXPECT_EQ(r.diagnostics[0].span.begin, 12u + kMaxNesting);
}

TEST(Parser, DeepNotChainIsACleanError) {
  std::string text = "modules(a); ";
  for (int i = 0; i < 100000; ++i) text += "not ";
  text += "(a.x = 1)";
  auto r = p(text);
  ASSERT_EQ(r.diagnostics.size(), 1u);
  EXPECT_NE(r.diagnostics[0].message.find("nested too deeply"), std::string::npos);
}

TEST(Parser, NestingJustUnderTheLimitParses) {
  const int depth = kMaxNesting - 1;
  auto r = p("modules(a); " + std::string(depth, '(') + "a.x = 1" + std::string(depth, ')'));
  EXPECT_TRUE(r.ok());
}

TEST(Parser, HugeExpressionIsACleanError) {
  std::string text = "modules(a); (a.x = 1)";
  for (int i = 0; i < 5000; ++i) text += " and (a.x = 1)";
  auto r = p(text);
  ASSERT_EQ(r.diagnostics.size(), 1u);
  EXPECT_NE(r.diagnostics[0].message.find("too large"), std::string::npos);
}

std::string chain(const char* step, int n) {
  std::string s;
  for (int i = 0; i < n; ++i) s += step;
  return s;
}

TEST(Parser, OffsetsUpToTheLimitParseAndPastItAreOneErrorAtTheirSpan) {
  auto ok =
      p("modules(a); (a." + chain("next.", kMaxOffset) + "x = 1) and (a." + chain("last.", kMaxOffset) + "x = 1)");
  EXPECT_TRUE(ok.ok());
  const std::string text = "modules(a); (a.y = 0) and (a." + chain("next.", 100'000) + "x = 1) and (a." +
                           chain("last.", kMaxOffset + 1) + "z = 1)";
  auto r = p(text);
  ASSERT_EQ(r.diagnostics.size(), 1u) << "one error for every offset out of range";
  EXPECT_NE(r.diagnostics[0].message.find("past 10000 steps"), std::string::npos) << r.diagnostics[0].message;
  EXPECT_EQ(r.diagnostics[0].span.begin, text.find("a.next")) << "at the module reference";
  EXPECT_GT(r.diagnostics[0].span.length(), 5u * kMaxOffset);
}

// A neighbour is read at its domain's offset plus its own: the limit holds for the sum, one error
// at the read; reads within it, either way, parse.
TEST(Parser, OffsetsThroughAnAggregateAddUpToTheLimit) {
  auto shifted = [](const char* name, const char* step, int n) {  // "a.next.next", no '.' after
    std::string m = std::string(name) + "." + chain(step, n);
    m.pop_back();
    return m;
  };
  const int half = kMaxOffset / 2;
  EXPECT_TRUE(p("modules(a); sum(n in neighbors(" + shifted("a", "next.", half) + "): " + shifted("n", "next.", half) +
                ".dist) > 1")
                  .ok());
  EXPECT_TRUE(p("modules(a); sum(n in within(" + shifted("a", "last.", half) + ", 2): " + shifted("n", "last.", half) +
                ".dist) > 1")
                  .ok());
  const std::string text = "modules(a); sum(n in neighbors(" + shifted("a", "next.", kMaxOffset) +
                           "): " + shifted("n", "next.", kMaxOffset) + ".dist) > 1";
  auto r = p(text);
  ASSERT_EQ(r.diagnostics.size(), 1u);
  EXPECT_NE(r.diagnostics[0].message.find("is 20000 steps ahead"), std::string::npos) << r.diagnostics[0].message;
  EXPECT_EQ(r.diagnostics[0].span.begin, text.find("n.next")) << "at the read";
  r = p("modules(a); count(n in neighbors(" + shifted("a", "last.", 6000) + "): " + shifted("n", "last.", 6000) +
        ".x = 1) > 1");
  ASSERT_EQ(r.diagnostics.size(), 1u);
  EXPECT_NE(r.diagnostics[0].message.find("is 12000 steps back"), std::string::npos) << r.diagnostics[0].message;
}

TEST(Parser, HugeExpressionSaysWhatItCounts) {
  std::string text = "modules(a); (a.x = 1)";
  for (int i = 0; i < 5000; ++i) text += " or (a.x = 1)";
  auto r = p(text);
  ASSERT_EQ(r.diagnostics.size(), 1u);
  EXPECT_NE(r.diagnostics[0].message.find("more than 4096 terms (comparisons, neighbor() tests"), std::string::npos)
      << r.diagnostics[0].message;
}

TEST(Parser, TooManySlotsIsOneError) {
  std::string text = "modules(";
  for (int i = 0; i < kMaxSlots + 5; ++i) text += " s" + std::to_string(i);
  auto r = p(text + "); (s0.x = 1)");
  ASSERT_EQ(r.diagnostics.size(), 1u);
  EXPECT_NE(r.diagnostics[0].message.find("at most 32"), std::string::npos);
  EXPECT_EQ(r.ast.slots.size(), static_cast<size_t>(kMaxSlots));
}

TEST(Parser, ParenthesesAroundAComparisonAreOptional) {
  auto a = p("modules(a b); (a.x = 1) and (b.y = 2)");
  auto b = p("modules(a b); a.x = 1 and b.y = 2");
  ASSERT_TRUE(a.ok());
  ASSERT_TRUE(b.ok());
  EXPECT_EQ(to_string(a.ast), to_string(b.ast));
}

TEST(Parser, ErrorsNeverEscapeAsExceptionsOnGarbage) {
  for (const char* text : {"", ";", "modules", "modules(", "modules(a", "modules(a)", "modules(a);(", "modules(a);((((",
                           "modules(a);a.", "modules(a);a.last.", "modules(a);neighbor(", "modules(a);not", ")))",
                           "modules(a);(a.x=1) and", "\xff\xfe", "modules(a);(a.x = -)"}) {
    auto r = p(text);
    EXPECT_FALSE(r.ok()) << text;
  }
}

}  // namespace
}  // namespace dw::watch
