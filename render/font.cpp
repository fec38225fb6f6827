#include "render/font.h"

#include <stb_truetype.h>

#include <cmath>
#include <fstream>
#include <iterator>

namespace dw::render {
namespace {

// Decodes the next UTF-8 character; anything past Latin-1, or malformed, is '?'.
uint32_t next_char(std::string_view s, size_t& i) {
  const auto c = uint8_t(s[i++]);
  if (c < 0x80) return c;
  uint32_t code = 0;
  int more = 0;
  if ((c & 0xE0) == 0xC0) code = c & 0x1F, more = 1;
  else if ((c & 0xF0) == 0xE0) code = c & 0x0F, more = 2;
  else if ((c & 0xF8) == 0xF0) code = c & 0x07, more = 3;
  else return '?';
  for (; more > 0; --more) {
    if (i >= s.size() || (uint8_t(s[i]) & 0xC0) != 0x80) return '?';
    code = (code << 6) | (uint8_t(s[i++]) & 0x3F);
  }
  return code;
}

}  // namespace

std::variant<FontAtlas, std::string> FontAtlas::bake(const std::string& ttf_path, float pixel_height) {
  std::ifstream in(ttf_path, std::ios::binary);
  if (!in) return "cannot read the font " + ttf_path;
  const std::vector<unsigned char> ttf((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());

  FontAtlas atlas;
  atlas.pixel_height_ = pixel_height;
  // Wide enough for every glyph at this size; four rows below them are a solid block.
  atlas.width_ = pixel_height <= 40 ? 512 : 1024;
  const int glyph_rows = atlas.width_;
  atlas.height_ = glyph_rows + 4;
  atlas.pixels_.assign(size_t(atlas.width_) * atlas.height_, 0);
  std::vector<stbtt_bakedchar> baked(kCount);
  const int rows = stbtt_BakeFontBitmap(ttf.data(), 0, pixel_height, atlas.pixels_.data(), atlas.width_, glyph_rows,
                                        kFirst, kCount, baked.data());
  if (rows <= 0) return "the font " + ttf_path + " does not fit its atlas at " + std::to_string(pixel_height) + " px";
  for (size_t i = size_t(glyph_rows) * atlas.width_; i < atlas.pixels_.size(); ++i) atlas.pixels_[i] = 255;
  atlas.white_u_ = 2.0f / float(atlas.width_);
  atlas.white_v_ = (float(glyph_rows) + 2.0f) / float(atlas.height_);

  for (const stbtt_bakedchar& b : baked) atlas.glyphs_.push_back({b.x0, b.y0, b.x1, b.y1, b.xoff, b.yoff, b.xadvance});

  stbtt_fontinfo info;
  if (!stbtt_InitFont(&info, ttf.data(), stbtt_GetFontOffsetForIndex(ttf.data(), 0)))
    return "the font " + ttf_path + " cannot be read";
  int ascent = 0, descent = 0, gap = 0;
  stbtt_GetFontVMetrics(&info, &ascent, &descent, &gap);
  atlas.ascent_ = float(ascent) * stbtt_ScaleForPixelHeight(&info, pixel_height);
  return atlas;
}

std::vector<FontAtlas::Quad> FontAtlas::layout(std::string_view text, float x, float y) const {
  std::vector<Quad> quads;
  const float iw = 1.0f / float(width_), ih = 1.0f / float(height_);
  for (size_t i = 0; i < text.size();) {
    uint32_t c = next_char(text, i);
    if (c < kFirst || c >= kFirst + kCount) c = '?';
    const Glyph& g = glyphs_[c - kFirst];
    // Glyphs start on whole pixels, so that text stays sharp.
    const float gx = std::round(x + g.xoff), gy = std::round(y + g.yoff);
    if (g.x1 > g.x0)
      quads.push_back(
          {gx, gy, gx + float(g.x1 - g.x0), gy + float(g.y1 - g.y0), g.x0 * iw, g.y0 * ih, g.x1 * iw, g.y1 * ih});
    x += g.xadvance;
  }
  return quads;
}

float FontAtlas::text_width(std::string_view text) const {
  float x = 0;
  for (size_t i = 0; i < text.size();) {
    uint32_t c = next_char(text, i);
    if (c < kFirst || c >= kFirst + kCount) c = '?';
    x += glyphs_[c - kFirst].xadvance;
  }
  return x;
}

}  // namespace dw::render
