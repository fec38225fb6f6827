// Text for the view's labels, title and legend: the glyphs of a TrueType font baked into one
// texture (stb_truetype), laid out left to right. Latin-1 is enough for what the view writes.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace dw::render {

class FontAtlas {
 public:
  // Bakes the font at `pixel_height`, or says why it cannot.
  static std::variant<FontAtlas, std::string> bake(const std::string& ttf_path, float pixel_height);

  // One glyph's rectangle on screen (pixels, y down) and in the atlas (0..1).
  struct Quad {
    float x0, y0, x1, y1;
    float u0, v0, u1, v1;
  };
  // The quads of a UTF-8 string whose baseline starts at (x, y); characters outside Latin-1 show
  // as '?'.
  std::vector<Quad> layout(std::string_view text, float x, float y) const;
  float text_width(std::string_view text) const;

  float pixel_height() const { return pixel_height_; }
  float ascent() const { return ascent_; }  // above the baseline, in pixels
  int width() const { return width_; }
  int height() const { return height_; }
  const std::vector<uint8_t>& pixels() const { return pixels_; }  // coverage, one byte per texel
  // A texel that is fully covered, for drawing solid shapes with the same texture.
  float white_u() const { return white_u_; }
  float white_v() const { return white_v_; }

 private:
  struct Glyph {
    uint16_t x0, y0, x1, y1;  // in the atlas
    float xoff, yoff, xadvance;
  };
  static constexpr int kFirst = 32, kCount = 224;  // ' ' to 'ÿ'
  std::vector<Glyph> glyphs_;
  std::vector<uint8_t> pixels_;
  int width_ = 0, height_ = 0;
  float pixel_height_ = 0, ascent_ = 0;
  float white_u_ = 0, white_v_ = 0;
};

}  // namespace dw::render
