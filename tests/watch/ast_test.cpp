#include "watch/ast.h"

#include <gtest/gtest.h>

#include "watch/parser.h"

namespace dw::watch {
namespace {

std::string normal(const std::string& text) {
  auto r = parse(SourceText("t", text));
  EXPECT_TRUE(r.ok()) << text;
  return to_string(r.ast);
}

TEST(NormalForm, GroupsMixedAndOrExplicitly) {
  EXPECT_EQ(normal("modules(a b); a.x = 2 and b.y = 1 or (a.y = b.y and b.x = 0)"),
            "modules(a b); ((a.x = 2) and (b.y = 1)) or ((a.y = b.y) and (b.x = 0))");
}

TEST(NormalForm, PrintsOffsetsAndNeighbor) {
  EXPECT_EQ(normal("modules(a,b);neighbor(a.last b.last) and not (b.next.x>=-3)"),
            "modules(a b); neighbor(a.last b.last) and not (b.next.x >= -3)");
}

TEST(NormalForm, IsIdempotent) {
  for (const char* text : {"modules(a x b); (x.token = 1) and (((a.last.token = 1) and (b.last.token = 1)) or "
                           "((a.last.token = 0) and (b.last.token = 0)))",
                           "modules(a b); not (a.x = 1 or b.x = 2) and not not (a.y < b.y)",
                           "modules(a b c); (a.x = 1) or (b.x = 1) and (c.x = 1) or neighbor(a c)"}) {
    const std::string once = normal(text);
    EXPECT_EQ(normal(once), once);
  }
}

TEST(NormalForm, ManyMinusSignsPrintWithinTheNestingTheyParsedIn) {
  // Found by the parser fuzzer: `-(-(-x))` doubled the nesting of 200 minus signs past the
  // parser's limit, so the normal form did not read back.
  EXPECT_EQ(normal("modules(a); - -(-a.x) = 1"), "modules(a); (- - -a.x = 1)");
  EXPECT_EQ(normal("modules(a); a.x = - -0 + - -5 + -(5)"), "modules(a); (a.x = - -0 + - -5 + -(5))");
  const std::string chain = "modules(a); a.x = " + std::string(200, '-') + "1";
  const std::string once = normal(chain);
  EXPECT_EQ(normal(once), once);
}

}  // namespace
}  // namespace dw::watch
