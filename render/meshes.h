// The shapes modules and props are drawn with, one unit across and centred on the origin, as
// triangle lists with a normal per vertex (flat faces, smooth round sides).
#pragma once

#include <vector>

#include "render/scene.h"

namespace dw::render {

struct MeshVertex {
  float position[3];
  float normal[3];
};

// A box from -0.5 to 0.5; an upright cylinder (axis z) of diameter 1 and height 1 with caps; a
// sphere of diameter 1.
std::vector<MeshVertex> make_mesh(Shape shape);

}  // namespace dw::render
