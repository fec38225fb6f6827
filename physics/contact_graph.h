// The neighbour graph from contacts (docs/design.md §8): one collision object per module in a
// collision-only Bullet world (the GJK detector for every pair, so that a gap is measured), the
// contact points of each pair's manifolds merged, a pair adjacent when some point lies within the
// threshold; module ids ride on setUserIndex.
//
// The graph is a pure function of the bodies: two modules of one rigid cluster are measured at
// their poses in the cluster's frame (which do not change while the cluster lasts), any other
// pair at its world poses. A pair is measured again, from an empty manifold, only when what it
// is measured at changed, and keeps its last measurement otherwise. So a still lattice, or one
// moving as a rigid whole, costs a walk over its pairs, and a restored world gives what the live
// one gave.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "physics/settings.h"
#include "sim/neighbor_graph.h"

class btCollisionShape;

namespace dw::physics {

class ContactGraph {
 public:
  ContactGraph(ModuleShape shape, float threshold);
  ~ContactGraph();
  ContactGraph(const ContactGraph&) = delete;
  ContactGraph& operator=(const ContactGraph&) = delete;

  // N(m) for the given bodies; absent modules touch nobody. Returns the previous graph (the same
  // object) when no pair changed.
  std::shared_ptr<const sim::NeighborGraph> update(const sim::Bodies& bodies, std::span<const uint8_t> present);
  // Forgets every measurement (the next update measures every pair).
  void reset();

  // Pairs measured by the last update (the others kept their measurement).
  uint64_t pairs_measured() const { return measured_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  uint64_t measured_ = 0;
};

}  // namespace dw::physics
