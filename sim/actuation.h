// What a host program asks of its module's body (docs/design.md §2, §8): a push, a lattice move, bonds
// released or made. Requests made during step t are carried out by the World when it moves on to
// t + 1, in module order; a World without bodies refuses them (a program error).
#pragma once

#include <cstdint>

#include "sim/bodies.h"

namespace dw::sim {

struct Actuation {
  enum class Kind : uint8_t {
    Push,        // an impulse (N s) at the module's centre, given to its cluster
    Move,        // a lattice move by `vector` (one module size) to a free cell
    Pivot,       // a pivot about the neighbour `other` into the cell at `vector` from here
    Release,     // release the bond with `other` (kGround: with the ground)
    ReleaseAll,  // release every bond
    Bond,        // latch to `other`, which must be touching
  };
  Kind kind = Kind::Push;
  ModuleId module = 0;
  ModuleId other = 0;
  Vec3 vector{};
};

}  // namespace dw::sim
