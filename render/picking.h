// Which module a pixel of the 3D view shows (the debugger's click and hover): the ray through the
// pixel, tested against every module's body, nearest hit first. Pure geometry, no GL: the same
// view-projection the renderer drew with (Renderer::view_projection) makes it exact.
#pragma once

#include <glm/glm.hpp>
#include <optional>

#include "render/scene.h"

namespace dw::render {

// The module under `pixel` (pixels from the image's top-left corner) of a width x height image,
// or nothing. A box or cylinder is tested as its box, a sphere as itself.
std::optional<sim::ModuleId> pick(const Scene& scene, const glm::mat4& view_projection, int width, int height,
                                  glm::vec2 pixel);

}  // namespace dw::render
