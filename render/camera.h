// The view's camera: set by the scenario, or fitted so that the whole ensemble shows, seen from
// above at an angle (steeper for a flat ensemble, so a hex sheet reads like the paper's Fig. 2).
#pragma once

#include <glm/glm.hpp>
#include <string>

#include "render/scene.h"

namespace dw::render {

// The part of the image the ensemble is fitted into, as fractions of its width and height from the
// top-left corner; the rest
// is left to the title and the legend.
struct Region {
  float left = 0, top = 0, right = 1, bottom = 1;
};

struct Camera {
  glm::vec3 eye{0, -10, 10};
  glm::vec3 target{0, 0, 0};
  glm::vec3 up{0, 0, 1};  // z is up
  float fov_y = glm::radians(30.0f);
  float near_plane = 0.1f, far_plane = 1000;
};

// Half a prop's extents along its own axes: a box of its size, or a sphere of diameter size[0].
glm::vec3 half_extent(const SceneProp& prop);

// The smallest box holding every module and prop (modules one size across).
struct Bounds {
  glm::vec3 min{0}, max{0};
  glm::vec3 center() const { return (min + max) * 0.5f; }
  float radius() const { return glm::length(max - min) * 0.5f; }
};
Bounds scene_bounds(const Scene& scene);

// The scenario's camera if it set one, else one fitted to the scene for an image of
// width x height whose ensemble goes into `region`.
Camera make_camera(const Scene& scene, int width, int height, const Region& region);

// Why a camera the user gave (an eye, or a target alone, from which make_camera derives the eye)
// draws none of the ensemble in an image of width x height, or "" when it draws some: every module
// behind it or outside its view, or all of them together under two pixels across (an eye
// thousands of module sizes away). A camera fitted without a target always sees them.
std::string camera_misses(const Scene& scene, int width, int height);

// World to clip space, the region's placement included.
glm::mat4 view_projection(const Camera& camera, int width, int height, const Region& region);

}  // namespace dw::render
