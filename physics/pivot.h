// The arc of a pivot (docs/design.md §8): a module turns about a neighbour into a free cell, as
// the field's modules move. A cube (Blinky Blocks, M-Blocks) turns about the edge it shares with
// the neighbour it rests on: by 90 degrees it rolls to the next cell along that neighbour's face
// side (the offset perpendicular to the way to the neighbour), by 180 it goes over the edge onto
// the neighbour's next face. A sphere or an upright cylinder (Catoms 3D, Catoms 2D) rolls over
// the neighbour into a cell that touches both: over its surface (about the line through it
// square to both cells), or, for a sphere, in the groove between it and one of the two cells
// touching all three (about the line through both: the catom keeps touching the two).
#pragma once

#include <string>
#include <variant>
#include <vector>

#include "physics/settings.h"
#include "sim/bodies.h"

namespace dw::physics {

struct PivotArc {
  sim::Vec3 pivot{}, axis{};  // the line turned about: a point on it, and its unit direction
  float angle = 0;            // radians, turned right-handed about axis
  float spin = 1;             // how far the body turns per radian of the arc
};

// The arcs that take a module centred at `from` about its neighbour centred at `about` into the
// cell at `from + offset`, in the order to try them (the first whose sweep is clear is taken),
// or what is wrong with the request.
std::variant<std::vector<PivotArc>, std::string> pivot_arcs(ModuleShape shape, const sim::Vec3& from,
                                                            const sim::Vec3& about, const sim::Vec3& offset);

}  // namespace dw::physics
