// What the view writes over the picture: the title, the groups' slot links and labels, and the
// legend of the colour scale. Built as an Overlay, without GL.
#pragma once

#include <glm/glm.hpp>
#include <optional>
#include <vector>

#include "render/camera.h"
#include "render/overlay.h"
#include "render/scene.h"

namespace dw::render {

// The text size for an image of this height, in pixels: a thirtieth of it, at least `least`
// (12 by default; the window asks for its panels' size, so that the 3D view's title and labels do
// not shrink to ~9 pixel letters in a small window) and at most 40.
int text_size(int height, int least = 12);

// Where the ensemble goes: below the title lines, right of the legend.
Region view_region(const Scene& scene, const FontAtlas& font, int width, int height);

// Where a point lands in the image (pixels, y down), or nothing behind the camera.
std::optional<glm::vec2> project(const glm::mat4& view_projection, glm::vec3 point, int width, int height);

// A point outside the image, pointed at from the image's edge (issue 64: a module that left the
// view had nothing saying where it went): the pointer's tip, `inset` pixels in from the edge on
// the line from the image's centre towards the point, and that direction (unit, y down). A point
// behind the camera is pointed at the way it lies from the view's axis. Nothing when it shows.
struct EdgePointer {
  glm::vec2 at;
  glm::vec2 toward;
};
std::optional<EdgePointer> edge_pointer(const glm::mat4& view_projection, glm::vec3 point, int width, int height,
                                        float inset);

// A rectangle of the image a label keeps off (the title, the group's caption, the legend).
struct Box {
  glm::vec2 min, max;
};

// Where a group's slot labels go (discs of `radius` pixels): each above its module (at `wanted`)
// where that is free, else the nearest free place around its module (`tops`: the modules' tops on
// screen), so that no two labels overlap however close the modules are on screen (at 11,000
// modules a group is a few pixels wide and the labels piled onto one spot), nor cover what is in
// `keep_clear` (a label's disc covered the caption's "(+23 more)"). Nothing where the module is
// not on screen.
std::vector<std::optional<glm::vec2>> place_labels(const std::vector<std::optional<glm::vec2>>& tops,
                                                   const std::vector<std::optional<glm::vec2>>& wanted, float radius,
                                                   const std::vector<Box>& keep_clear = {});

// The title (and the first group's watch, step and slot bindings), each group's slots linked in
// slot order with a label above each slot, and the legend.
void annotate(Overlay& overlay, const Scene& scene, const glm::mat4& view_projection, int width, int height);

}  // namespace dw::render
