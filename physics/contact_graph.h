// The neighbour graph from contacts (docs/design.md §8): two modules are neighbours when Bullet's
// GJK puts their shapes at most the threshold apart, or when one pivots on the other (its
// sim::Mover::hinge: they touch along the edge it turns about, which the margins round off in the
// middle of a cube's turn). Candidates come from a grid of module centres (physics/cell_grid.h);
// no Bullet world, collision object or pair cache is kept.
//
// The graph is a pure function of the bodies: two modules of one rigid cluster that moves are
// measured at their poses in the cluster's frame (which do not change while the cluster lasts),
// any other pair at its world poses (an anchored cluster never moves). A pair is measured again
// only when what it is measured at changed since the last update, and keeps its measurement
// otherwise, whatever state that update saw. So a still lattice, one moving as a rigid whole, or
// a latched block that a few modules leave and join costs a walk over its modules, and a world
// restored to any state gives what the live one gave.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "physics/settings.h"
#include "sim/neighbor_graph.h"
#include "sim/rank_exchange.h"
#include "sim/worker_pool.h"

class btCollisionShape;

namespace dw::physics {

class ContactGraph {
 public:
  ContactGraph(ModuleShape shape, float threshold);
  ~ContactGraph();
  ContactGraph(const ContactGraph&) = delete;
  ContactGraph& operator=(const ContactGraph&) = delete;

  // N(m) for the given bodies; absent modules touch nobody. Returns the previous graph (the same
  // object) when no pair changed. Pairs are measured on `workers`, the modules split among them.
  // `changed`, when given, lists every module whose presence, world pose or frame may differ from
  // the last update (the others are known not to, and are not compared: a million-module block
  // with a thousand moving is not walked); without it every module is compared. Over `ranks` (a
  // collective call, made alike on every rank with the same bodies), each rank gets its window of
  // the graph one process gets (NeighborGraph::held): the lists of the modules it owns (`owners`)
  // and of those within reach of them, each whole, measured by the rank itself; no pair is sent.
  std::shared_ptr<const sim::NeighborGraph> update(const sim::Bodies& bodies, std::span<const uint8_t> present,
                                                   sim::WorkerPool& workers,
                                                   const std::vector<sim::ModuleId>* changed = nullptr,
                                                   sim::RankExchange* ranks = nullptr,
                                                   const sim::ModuleOwners* owners = nullptr);
  // Brings the grid of module centres up to the bodies without measuring (update does it too):
  // what near() reads.
  void place(const sim::Bodies& bodies, std::span<const uint8_t> present);
  // The present modules whose centres lie closer than `radius` (at most reach()) to `at`,
  // ascending, as last placed.
  std::vector<sim::ModuleId> near(const sim::Vec3& at, float radius) const;
  // The distance between two module shapes at these poses (negative: they overlap; huge: further
  // apart than the threshold), and how far apart two centres may be and the shapes still touch.
  float distance(const sim::Pose& a, const sim::Pose& b) const;
  float reach() const;
  // Whether two modules at these poses are neighbours (GJK's distance within the threshold, in
  // closed form for spheres and unturned boxes).
  bool touching(const sim::Pose& a, const sim::Pose& b) const;
  // Forgets every measurement (the next update measures every pair).
  void reset();

  // Pairs measured by the last update (the others kept their measurement), over ranks as one
  // process measures them (each counted by the owner of the module it is measured from).
  uint64_t pairs_measured() const { return measured_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  uint64_t measured_ = 0;
};

}  // namespace dw::physics
