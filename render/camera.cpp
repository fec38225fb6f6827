#include "render/camera.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <optional>
#include <vector>

namespace dw::render {
namespace {

float region_aspect(int width, int height, const Region& r) {
  return (r.right - r.left) * float(width) / std::max(1.0f, (r.bottom - r.top) * float(height));
}

// Near and far planes around the bounds (and the ground grid, which reaches past them).
void fit_depth(Camera& c, const Bounds& b) {
  const float distance = glm::length(c.eye - b.center());
  const float reach = b.radius() * 4 + 4;
  c.near_plane = std::max(0.05f, (distance - reach) * 0.5f);
  c.far_plane = distance + reach;
}

// The module whose shape, grown by the near plane's distance (what the camera clips), holds the
// eye: from there the view shows the inside of its faces, a tinted picture of nothing.
std::optional<sim::ModuleId> module_around(const Scene& scene, glm::vec3 eye, float near_plane) {
  const float half = 0.5f + near_plane;
  for (const SceneModule& m : scene.modules) {
    const auto& q = m.pose.orientation;
    const glm::vec3 local = glm::inverse(glm::quat(q[3], q[0], q[1], q[2])) *
                            (eye - glm::vec3(m.pose.position[0], m.pose.position[1], m.pose.position[2]));
    const float radial = glm::length(glm::vec2(local));
    const bool inside = scene.module_shape == Shape::Sphere ? glm::length(local) < half
                        : scene.module_shape == Shape::Cylinder
                            ? radial < half && std::abs(local.z) < half
                            : glm::all(glm::lessThan(glm::abs(local), glm::vec3(half)));
    if (inside) return m.id;
  }
  return std::nullopt;
}

}  // namespace

glm::vec3 half_extent(const SceneProp& prop) {
  if (prop.shape == Shape::Sphere) return glm::vec3(prop.size[0] * 0.5f);
  return glm::vec3(prop.size[0], prop.size[1], prop.size[2]) * 0.5f;
}

Bounds scene_bounds(const Scene& scene) {
  Bounds b{glm::vec3(1e30f), glm::vec3(-1e30f)};
  auto add = [&](const sim::Vec3& p, glm::vec3 half) {
    const glm::vec3 c(p[0], p[1], p[2]);
    b.min = glm::min(b.min, c - half);
    b.max = glm::max(b.max, c + half);
  };
  for (const SceneModule& m : scene.modules) add(m.pose.position, glm::vec3(0.5f));
  for (const SceneProp& p : scene.props) add(p.pose.position, half_extent(p));
  if (scene.modules.empty() && scene.props.empty()) return Bounds{};
  return b;
}

Camera make_camera(const Scene& scene, int width, int height, const Region& region) {
  Camera c;
  const Bounds b = scene_bounds(scene);
  if (scene.camera_eye) {
    const auto& e = *scene.camera_eye;
    c.eye = {e[0], e[1], e[2]};
    if (scene.camera_target) {
      const auto& t = *scene.camera_target;
      c.target = {t[0], t[1], t[2]};
    } else {
      c.target = b.center();
    }
    // An eye on the target looks nowhere (the inputs refuse one within a millionth of its
    // distance, scenarios::camera_problem; an eye at the ensemble's centre can still meet it): the
    // fitted camera below is drawn instead.
    const glm::vec3 view = c.target - c.eye;
    if (glm::length(view) > 1e-7f * std::max(1.0f, glm::length(c.eye))) {
      // Straight down (or up), z cannot be the picture's up: y is, as on a 2-D lattice's plan.
      if (glm::length(glm::cross(glm::normalize(view), c.up)) < 1e-3f) c.up = {0, 1, 0};
      fit_depth(c, b);
      return c;
    }
  }

  // From the front-right, above; a flat ensemble from higher up.
  const bool flat = b.max.z - b.min.z <= 1.01f;
  const float elevation = glm::radians(flat ? 58.0f : 28.0f);
  const float azimuth = glm::radians(flat ? -72.0f : -58.0f);
  const glm::vec3 back(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                       std::sin(elevation));
  c.target = b.center();
  if (scene.camera_target) c.target = {(*scene.camera_target)[0], (*scene.camera_target)[1], (*scene.camera_target)[2]};

  // What must show: the corners of every module's and prop's box (not just of the bounds, whose
  // corners can lie far outside a ring or a diagonal line).
  std::vector<glm::vec3> points;
  auto add = [&](const sim::Vec3& p, glm::vec3 half) {
    for (int i = 0; i < 8; ++i)
      points.push_back(glm::vec3(p[0], p[1], p[2]) +
                       half * glm::vec3((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1));
  };
  for (const SceneModule& m : scene.modules) add(m.pose.position, glm::vec3(0.5f));
  for (const SceneProp& p : scene.props) add(p.pose.position, half_extent(p));

  // The distance at which every point lies inside the field of view: a point at offset (x, y)
  // across the view and z towards the camera needs distance >= |x| / tan(half width) + z, and
  // likewise for y.
  const glm::vec3 forward = -back;
  const glm::vec3 right = glm::normalize(glm::cross(forward, c.up));
  const glm::vec3 up = glm::cross(right, forward);
  const float tan_y = std::tan(c.fov_y * 0.5f);
  const float tan_x = tan_y * region_aspect(width, height, region);
  float distance = 1;
  for (const glm::vec3& point : points) {
    const glm::vec3 rel = point - c.target;
    const float toward = glm::dot(rel, back);
    distance = std::max(distance, std::abs(glm::dot(rel, right)) / tan_x + toward);
    distance = std::max(distance, std::abs(glm::dot(rel, up)) / tan_y + toward);
  }
  c.eye = c.target + back * distance;
  fit_depth(c, b);

  // Perspective makes the near side larger than the far side, so the bounds' centre is not the
  // picture's: look at what the points cover on screen, move the target to its middle and the
  // camera in or out until it fills the view with a small margin (converges in a few rounds).
  for (int round = 0; round < 4; ++round) {
    const glm::mat4 vp = glm::perspective(c.fov_y, region_aspect(width, height, region), c.near_plane, c.far_plane) *
                         glm::lookAt(c.eye, c.target, c.up);
    glm::vec2 lo(1e9f), hi(-1e9f);
    for (const glm::vec3& point : points) {
      const glm::vec4 p = vp * glm::vec4(point, 1);
      const glm::vec2 ndc = glm::vec2(p) / p.w;
      lo = glm::min(lo, ndc);
      hi = glm::max(hi, ndc);
    }
    const glm::vec2 middle = (lo + hi) * 0.5f;
    const float fill = std::max(hi.x - lo.x, hi.y - lo.y) * 0.5f / 0.94f;  // the margin: 3% a side
    const float d = glm::length(c.eye - c.target);
    c.target += right * (middle.x * d * tan_x) + up * (middle.y * d * tan_y);
    c.eye = c.target + back * (d * fill);
    fit_depth(c, b);
  }
  return c;
}

std::string camera_misses(const Scene& scene, int width, int height) {
  // A target alone moves the fitted camera too: its eye is derived from the target (make_camera)
  // and can end up seeing nothing (a target far off), so that camera is checked as well.
  if ((!scene.camera_eye && !scene.camera_target) || scene.modules.empty()) return "";
  const Region whole;
  const Camera c = make_camera(scene, width, height, whole);
  const glm::mat4 vp = view_projection(c, width, height, whole);
  // A module's reach on screen: its bounding sphere's radius over its distance, in half-heights.
  const float radius = std::sqrt(3.0f) * 0.5f, tan_y = std::tan(c.fov_y * 0.5f);
  const float aspect = float(width) / float(height);
  glm::vec2 lo(1e30f), hi(-1e30f);
  for (const SceneModule& m : scene.modules) {
    const glm::vec4 p = vp * glm::vec4(m.pose.position[0], m.pose.position[1], m.pose.position[2], 1);
    if (p.w <= c.near_plane) continue;  // behind the eye, or at it
    const glm::vec2 reach(radius / (p.w * tan_y * aspect), radius / (p.w * tan_y));
    const glm::vec2 ndc = glm::vec2(p) / p.w;
    if (std::abs(ndc.x) > 1 + reach.x || std::abs(ndc.y) > 1 + reach.y) continue;
    lo = glm::min(lo, glm::max(ndc - reach, glm::vec2(-1)));
    hi = glm::max(hi, glm::min(ndc + reach, glm::vec2(1)));
  }
  const Bounds b = scene_bounds(scene);
  const std::optional<sim::ModuleId> around = module_around(scene, c.eye, c.near_plane);
  auto at = [](glm::vec3 v) {
    char text[96];
    std::snprintf(text, sizeof text, "%g,%g,%g", double(v.x), double(v.y), double(v.z));
    return std::string(text);
  };
  // What the user gave, where given: a camera fitted around a given target moves that target.
  const auto given = [](const std::optional<sim::Vec3>& v, glm::vec3 otherwise) {
    return v ? glm::vec3((*v)[0], (*v)[1], (*v)[2]) : otherwise;
  };
  const std::string where =
      "the camera at " + at(given(scene.camera_eye, c.eye)) + " looking at " + at(given(scene.camera_target, c.target));
  const std::string ensemble = "the ensemble lies in " + at(b.min) + " to " + at(b.max);
  if (around)
    return where + " is inside module " + std::to_string(*around) + " (" + ensemble +
           "): move it out, or give no camera to have it fitted";
  if (lo.x > hi.x)
    return where + " sees none of the modules (" + ensemble + "): aim it at them, or give no camera to have it fitted";
  const float pixels = std::max((hi.x - lo.x) * float(width), (hi.y - lo.y) * float(height)) * 0.5f;
  if (pixels < 2)
    return where + " sees the modules under 2 pixels across (" + ensemble +
           "): move it closer, or give no camera to have it fitted";
  return "";
}

glm::mat4 view_projection(const Camera& camera, int width, int height, const Region& region) {
  const glm::mat4 view = glm::lookAt(camera.eye, camera.target, camera.up);
  const glm::mat4 projection =
      glm::perspective(camera.fov_y, region_aspect(width, height, region), camera.near_plane, camera.far_plane);
  // Maps the full clip square onto the region: scale, then move its centre (y up in clip space).
  const float sx = region.right - region.left, sy = region.bottom - region.top;
  const float cx = (region.left + region.right) - 1, cy = 1 - (region.top + region.bottom);
  glm::mat4 place(1.0f);
  place[0][0] = sx;
  place[1][1] = sy;
  place[3][0] = cx;
  place[3][1] = cy;
  return place * projection * view;
}

}  // namespace dw::render
