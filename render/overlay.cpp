#include "render/overlay.h"

#include <algorithm>
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
  const glm::vec2 normal = glm::vec2(-d.y, d.x) / length;
  const glm::vec2 core = normal * std::max(0.0f, width * 0.5f - 0.5f), edge = normal * (width * 0.5f + 0.5f);
  const glm::vec4 clear(color.r, color.g, color.b, 0);
  for (glm::vec2 p : {a + core, b + core, b - core, a + core, b - core, a - core}) solid(p, color);
  // A pixel-wide fringe on either side fading out: the edges are anti-aliased.
  for (float side : {1.0f, -1.0f}) {
    const glm::vec2 in = core * side, out = edge * side;
    solid(a + in, color), solid(b + in, color), solid(b + out, clear);
    solid(a + in, color), solid(b + out, clear), solid(a + out, clear);
  }
}

void Overlay::disc(glm::vec2 center, float radius, glm::vec4 color) {
  // Enough segments that the edge looks round at this size, and a pixel-wide fringe fading out.
  const int segments = std::max(16, int(radius * 1.5f));
  const glm::vec4 clear(color.r, color.g, color.b, 0);
  const float inner = std::max(0.0f, radius - 0.5f), outer = radius + 0.5f;
  for (int i = 0; i < segments; ++i) {
    const float a0 = 2 * std::numbers::pi_v<float> * float(i) / float(segments);
    const float a1 = 2 * std::numbers::pi_v<float> * float(i + 1) / float(segments);
    const glm::vec2 u0(std::cos(a0), std::sin(a0)), u1(std::cos(a1), std::sin(a1));
    solid(center, color), solid(center + inner * u0, color), solid(center + inner * u1, color);
    solid(center + inner * u0, color), solid(center + outer * u0, clear), solid(center + outer * u1, clear);
    solid(center + inner * u0, color), solid(center + outer * u1, clear), solid(center + inner * u1, color);
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
