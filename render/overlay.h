// The flat layer drawn over the 3D view: links between the slots of a match, slot labels, the
// title and the legend. A list of triangles in pixels (y down), textured by the font atlas, whose
// solid texel draws plain shapes, so that one draw call paints all of it.
#pragma once

#include <glm/glm.hpp>
#include <string_view>
#include <vector>

#include "render/font.h"

namespace dw::render {

struct OverlayVertex {
  float x, y;  // pixels from the top-left corner
  float u, v;
  float r, g, b, a;
};

class Overlay {
 public:
  explicit Overlay(const FontAtlas& font) : font_(font) {}

  void rect(glm::vec2 min, glm::vec2 max, glm::vec4 color);
  // A band of `width` pixels from a to b.
  void line(glm::vec2 a, glm::vec2 b, float width, glm::vec4 color);
  void disc(glm::vec2 center, float radius, glm::vec4 color);
  // Text whose baseline starts at `at`; returns its width.
  float text(glm::vec2 at, std::string_view s, glm::vec4 color);

  const FontAtlas& font() const { return font_; }
  const std::vector<OverlayVertex>& vertices() const { return vertices_; }

 private:
  void solid(glm::vec2 p, glm::vec4 c);

  const FontAtlas& font_;
  std::vector<OverlayVertex> vertices_;
};

}  // namespace dw::render
