// The arc of a pivot (docs/design.md §8): a module turns about a neighbour into a free cell, as
// the field's modules move. A cube (Blinky Blocks, M-Blocks) turns about the edge it shares with
// the neighbour it rests on: by 90 degrees it rolls to the next cell along that neighbour's face
// side (the offset perpendicular to the way to the neighbour), by 180 it goes over the edge onto
// the neighbour's next face. A sphere or an upright cylinder (Catoms 3D, Catoms 2D) rolls over
// the neighbour into a cell that touches both: over its surface (about the line through it
// square to both cells), or, for a sphere, in the groove between it and one of the two cells
// touching all three (about the line through both: the catom keeps touching the two). A
// Hexanode (an upright hexagonal prism) turns about the vertical edge it shares with the
// neighbour and with the cell it goes to, by 120 degrees.
//
// In a vertical plane (hex2d_vertical: 2-D catoms against gravity) a pivot must also leave the
// module supported where it arrives (supported_in_vertical_plane).
#pragma once

#include <optional>
#include <span>
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

// A module next to the cell a pivot goes to: its id and its centre.
struct Holder {
  sim::ModuleId id = 0;
  sim::Vec3 centre{};
};
// Whether a module of a vertical plane may come to rest in the cell centred at `cell`, given the
// still modules that touch that cell (the mover itself not among them): it rests on the ground,
// or on a module below its centre, or is held between at least two modules. Otherwise (hanging
// from one neighbour's side, or from nothing) what is wrong, naming the neighbour it would hang
// from. A catom latches to what it touches on arrival, so one resting on something, or latched
// on two sides, stays; one latched on one side only would hang on a single latch's hold.
std::optional<std::string> unsupported_in_vertical_plane(const sim::Vec3& cell, float ground_z,
                                                         std::span<const Holder> touching);

}  // namespace dw::physics
