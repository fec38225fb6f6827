#include "render/font.h"

#include <gtest/gtest.h>

namespace dw::render {
namespace {

const FontAtlas& font() {
  static const FontAtlas atlas = std::get<FontAtlas>(FontAtlas::bake(DWATCH_FONT_FILE, 20));
  return atlas;
}

TEST(FontAtlas, BakesGlyphsAndASolidBlock) {
  const FontAtlas& f = font();
  EXPECT_EQ(f.pixels().size(), size_t(f.width()) * f.height());
  const int wx = int(f.white_u() * f.width()), wy = int(f.white_v() * f.height());
  EXPECT_EQ(f.pixels()[size_t(wy) * f.width() + wx], 255);
  EXPECT_GT(f.ascent(), 10);
  EXPECT_LT(f.ascent(), 20);
}

TEST(FontAtlas, LaysOutOneQuadPerVisibleCharacterLeftToRight) {
  const auto quads = font().layout("ab c", 100, 50);
  ASSERT_EQ(quads.size(), 3u);  // the space has no quad
  EXPECT_LT(quads[0].x0, quads[1].x0);
  EXPECT_LT(quads[1].x1, quads[2].x0);
  EXPECT_GE(quads[0].x0, 100);
  EXPECT_LE(quads[0].y0, 50);  // above the baseline
  for (const auto& q : quads) {
    EXPECT_LT(q.u0, q.u1);
    EXPECT_LT(q.v0, q.v1);
  }
}

TEST(FontAtlas, WidthGrowsWithTheTextAndLatin1Decodes) {
  EXPECT_GT(font().text_width("two_leaders"), font().text_width("two"));
  EXPECT_EQ(font().layout("\xC2\xB7", 0, 0).size(), 1u);  // the middle dot, one glyph
  // Outside Latin-1 (an emoji) and malformed UTF-8 show as '?'.
  EXPECT_EQ(font().text_width("\xF0\x9F\x98\x80"), font().text_width("?"));
  EXPECT_EQ(font().text_width("\xC2"), font().text_width("?"));
}

TEST(FontAtlas, AMissingFontIsAnError) {
  auto r = FontAtlas::bake("/nonexistent/font.ttf", 20);
  ASSERT_TRUE(std::holds_alternative<std::string>(r));
  EXPECT_NE(std::get<std::string>(r).find("/nonexistent/font.ttf"), std::string::npos);
}

}  // namespace
}  // namespace dw::render
