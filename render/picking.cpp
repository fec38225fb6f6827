#include "render/picking.h"

#include <cmath>
#include <glm/gtc/quaternion.hpp>
#include <limits>

namespace dw::render {
namespace {

// The distance along the ray (origin o, direction d, in the module's own frame) at which it
// enters the unit body, or a negative number when it misses.
float hit_distance(Shape shape, glm::vec3 o, glm::vec3 d) {
  if (shape == Shape::Sphere) {
    const float b = glm::dot(o, d), c = glm::dot(o, o) - 0.25f;
    const float disc = b * b - c;
    return disc < 0 ? -1 : -b - std::sqrt(disc);
  }
  float near = -std::numeric_limits<float>::infinity(), far = std::numeric_limits<float>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(d[axis]) < 1e-12f) {
      if (std::abs(o[axis]) > 0.5f) return -1;
      continue;
    }
    float a = (-0.5f - o[axis]) / d[axis], b = (0.5f - o[axis]) / d[axis];
    if (a > b) std::swap(a, b);
    near = std::max(near, a);
    far = std::min(far, b);
  }
  return near <= far && far >= 0 ? near : -1;
}

}  // namespace

std::optional<sim::ModuleId> pick(const Scene& scene, const glm::mat4& view_projection, int width, int height,
                                  glm::vec2 pixel) {
  if (width < 1 || height < 1) return std::nullopt;
  const glm::vec2 ndc(pixel.x / float(width) * 2 - 1, 1 - pixel.y / float(height) * 2);
  const glm::mat4 inverse = glm::inverse(view_projection);
  const glm::vec4 a = inverse * glm::vec4(ndc, -1, 1), b = inverse * glm::vec4(ndc, 1, 1);
  const glm::vec3 origin = glm::vec3(a) / a.w;
  const glm::vec3 direction = glm::normalize(glm::vec3(b) / b.w - origin);

  std::optional<sim::ModuleId> nearest;
  float best = std::numeric_limits<float>::infinity();
  for (const SceneModule& m : scene.modules) {
    if (!shown(scene, m)) continue;  // left out by isolate or the cut: what shows behind it is hit
    const auto& p = m.pose.position;
    const auto& q = m.pose.orientation;  // x, y, z, w
    const glm::quat to_local = glm::conjugate(glm::quat(q[3], q[0], q[1], q[2]));
    const glm::vec3 o = to_local * (origin - glm::vec3(p[0], p[1], p[2]));
    const float distance = hit_distance(scene.module_shape, o, to_local * direction);
    if (distance >= 0 && distance < best) {
      best = distance;
      nearest = m.id;
    }
  }
  return nearest;
}

}  // namespace dw::render
