#include "render/overlay.h"

#include <cmath>
#include <numbers>

namespace dw::render {

void Overlay::solid(glm::vec2 p, glm::vec4 c) {
  vertices_.push_back({p.x, p.y, font_.white_u(), font_.white_v(), c.r, c.g, c.b, c.a});
}

void Overlay::rect(glm::vec2 min, glm::vec2 max, glm::vec4 color) {
  for (glm::vec2 p : {min, glm::vec2(max.x, min.y), max, min, max, glm::vec2(min.x, max.y)}) solid(p, color);
}

void Overlay::line(glm::vec2 a, glm::vec2 b, float width, glm::vec4 color) {
  const glm::vec2 d = b - a;
  const float length = glm::length(d);
  if (length <= 0) return;
  const glm::vec2 n = glm::vec2(-d.y, d.x) / length * (width * 0.5f);
  for (glm::vec2 p : {a + n, b + n, b - n, a + n, b - n, a - n}) solid(p, color);
}

void Overlay::disc(glm::vec2 center, float radius, glm::vec4 color) {
  // Enough segments that the edge looks round at this size.
  const int segments = std::max(16, int(radius * 1.5f));
  for (int i = 0; i < segments; ++i) {
    const float a0 = 2 * std::numbers::pi_v<float> * float(i) / float(segments);
    const float a1 = 2 * std::numbers::pi_v<float> * float(i + 1) / float(segments);
    solid(center, color);
    solid(center + radius * glm::vec2(std::cos(a0), std::sin(a0)), color);
    solid(center + radius * glm::vec2(std::cos(a1), std::sin(a1)), color);
  }
}

float Overlay::text(glm::vec2 at, std::string_view s, glm::vec4 c) {
  for (const FontAtlas::Quad& q : font_.layout(s, at.x, at.y)) {
    const OverlayVertex v[4] = {{q.x0, q.y0, q.u0, q.v0, c.r, c.g, c.b, c.a},
                                {q.x1, q.y0, q.u1, q.v0, c.r, c.g, c.b, c.a},
                                {q.x1, q.y1, q.u1, q.v1, c.r, c.g, c.b, c.a},
                                {q.x0, q.y1, q.u0, q.v1, c.r, c.g, c.b, c.a}};
    for (int i : {0, 1, 2, 0, 2, 3}) vertices_.push_back(v[i]);
  }
  return font_.text_width(s);
}

}  // namespace dw::render
