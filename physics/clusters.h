// Rigid clusters (sim/bodies.h): the modules latched together by bonds move as one body.
#pragma once

#include <span>

#include "sim/bodies.h"

class btCollisionShape;

namespace dw::physics {

// Regroups the modules into clusters after bonds changed: the components of the bond graph among
// present modules that are not making a lattice move, ordered by their smallest member, members
// ascending. See settle for their frames. physics/regroup.h does the same by looking only at
// what changed.
void form_clusters(sim::Bodies& bodies, std::span<const uint8_t> present, btCollisionShape& module_shape);

// The frame of cluster `c` with members `mine` (ascending), while b.clusters, b.members and
// b.cluster_of still hold the clusters before regrouping: a cluster with the same members, held
// by the ground or not as before, keeps its frame bit for bit (so that a still lattice stays
// still); an anchored one gets the world's frame (its members' local poses are their world poses)
// and no velocity; any other the principal frame of its members' world poses and their mean
// velocity.
void settle(sim::Bodies& b, sim::Cluster& c, std::span<const sim::ModuleId> mine, btCollisionShape& module_shape);

// The world pose and velocity of every member of the clusters that are not anchored, from their
// frames.
void place_members(sim::Bodies& bodies);

}  // namespace dw::physics
