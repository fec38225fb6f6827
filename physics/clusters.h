// Rigid clusters (sim/bodies.h): the modules latched together by bonds move as one body.
#pragma once

#include <span>

#include "sim/bodies.h"

class btCollisionShape;

namespace dw::physics {

// Regroups the modules into clusters after bonds changed: the components of the bond graph among
// present modules that are not making a lattice move. A cluster whose members did not change
// keeps its frame bit for bit (so that a still lattice stays still) unless the ground let go of
// it; a new one gets the principal frame of its members' world poses and their mean velocity; an
// anchored one the world's frame (its members' local poses are their world poses) and none.
void form_clusters(sim::Bodies& bodies, std::span<const uint8_t> present, btCollisionShape& module_shape);

// The world pose and velocity of every member of the clusters that are not anchored, from their
// frames.
void place_members(sim::Bodies& bodies);

}  // namespace dw::physics
