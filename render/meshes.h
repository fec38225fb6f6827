// The shapes modules and props are drawn with, one unit across and centred on the origin, as
// triangle lists with a normal per vertex (flat faces, smooth round sides).
#pragma once

#include <cstdint>
#include <vector>

#include "render/scene.h"

namespace dw::render {

struct MeshVertex {
  float position[3];
  float normal[3];
};

// A box from -0.5 to 0.5; an upright cylinder (axis z) of diameter 1 and height 1 with caps; a
// sphere of diameter 1; a disc, that cylinder lying along y; an upright hexagonal prism one across
// its faces and one high.
std::vector<MeshVertex> make_mesh(Shape shape);

// The same triangles, in the same order, with each distinct vertex stored once and the triangles
// as indices into them: a software rasteriser (llvmpipe) shades a corner shared by several
// triangles once per instance instead of once per triangle (a box: 24 vertices, not 36).
struct IndexedMesh {
  std::vector<MeshVertex> vertices;
  std::vector<uint32_t> indices;
};
IndexedMesh make_indexed_mesh(Shape shape);

}  // namespace dw::render
