// Regrouping the clusters (physics/clusters.h) by looking only at what changed: a few modules
// leaving or joining a latched block of a million must not cost a pass over its 3 million bonds.
// The result is form_clusters' to the bit (tests/physics/regroup_test.cpp holds them side by side).
//
// Bonds only ever join modules of one cluster, so a bond made can only merge clusters, and only
// a bond gone (with the modules setting off, released, broken) can split one. A cluster that lost
// bonds is searched from the members those bonds held, one search per member run in turn, a step
// each: searches that meet join, and a search that runs out of modules has found a piece cut off.
// When one search is left, what it has not reached of the cluster is the rest, in one piece: so a
// split costs the size of the smaller pieces, and a hole in a block the few steps its neighbours
// need to meet around it.
#pragma once

#include <algorithm>
#include <memory>
#include <span>
#include <vector>

#include "sim/bodies.h"

class btCollisionShape;

namespace dw::physics {

// The bonds of each module, both ways. The set gives a module's bonds to larger ids and to the
// ground (BondSet::above) and those to lattice neighbours below it (BondSet::linked_below); this
// keeps the listed bonds (those not between lattice neighbours) sorted by (b, a), for those to
// smaller ids.
class BondIndex {
 public:
  // Forgets everything: the next use builds it from the bonds.
  void invalidate() { valid_ = false; }
  bool valid() const { return valid_; }
  void rebuild(const sim::BondSet& bonds);
  // Brings it from the bonds before to those after these changes (each sorted, module-module and
  // ground bonds alike).
  void apply(const sim::BondSet& bonds, std::span<const sim::Bond> removed, std::span<const sim::Bond> added);
  // Calls f(o) for every module o bonded to m (not the ground).
  template <class F>
  void partners(const sim::BondSet& bonds, sim::ModuleId m, F&& f) const {
    bonds_of(bonds, m, [&](const sim::Bond& x) {
      if (x.b != sim::kGround) f(x.a == m ? x.b : x.a);
    });
  }
  // Calls f(bond) for every bond with m as an end, the ground's too.
  template <class F>
  void bonds_of(const sim::BondSet& bonds, sim::ModuleId m, F&& f) const {
    bonds.above(m, [&](sim::ModuleId o) { f(sim::Bond{m, o}); });
    bonds.linked_below(m, [&](sim::ModuleId o) { f(sim::Bond{o, m}); });
    for (auto at = std::lower_bound(reversed_.begin(), reversed_.end(), sim::Bond{m, 0});
         at != reversed_.end() && at->a == m; ++at)
      f(sim::Bond{at->b, m});
  }

 private:
  std::vector<sim::Bond> reversed_;  // {b, a} of every listed module-module bond, sorted
  bool valid_ = false;
};

// What changed since the clusters were last formed: bonds gone and made (module-module and
// ground alike), and modules that stopped or started being still (setting off on or ending a
// lattice move). A module that sets off has its bonds in `removed`.
struct BondChanges {
  std::vector<sim::Bond> removed, added;
  std::vector<sim::ModuleId> stopped, started;
  bool empty() const { return removed.empty() && added.empty() && stopped.empty() && started.empty(); }
  void clear();
  // Sorts each list and drops repeats; a bond made and gone within the changes is in the list of
  // what it ended as, or in neither.
  void normalize();
};

// Regroups b's clusters, formed before `changes` (normalized), as form_clusters would after them;
// b.bonds, b.movers, `present` and `index` are as after them. Its scratch is kept between calls.
class Regrouper {
 public:
  Regrouper();
  ~Regrouper();
  void operator()(sim::Bodies& b, std::span<const uint8_t> present, const BondChanges& changes, const BondIndex& index,
                  btCollisionShape& module_shape);
  // Modules the searches of the last call took from their queues.
  uint64_t searched() const { return searched_; }
  // Modules whose frame (physics/contact_graph.h: their cluster, if it moves, and their pose in
  // it) the last call may have changed; none other's changed.
  const std::vector<sim::ModuleId>& reframed() const { return reframed_; }

 private:
  struct Piece;
  struct Scratch;
  struct Made;
  // The stages of a call, in order (regroup.cpp).
  void find_changed(const sim::Bodies& b, const BondChanges& changes);
  void cut_pieces(const sim::Bodies& b, const BondChanges& changes, const BondIndex& index);
  void search(const sim::Bodies& b, const BondIndex& index, uint32_t cluster, std::span<const sim::ModuleId> seeds);
  std::vector<Made> join_pieces(const sim::Bodies& b, const BondChanges& changes);
  void frame_clusters(sim::Bodies& b, const BondChanges& changes, std::vector<Made>& made,
                      btCollisionShape& module_shape);
  void put_clusters(sim::Bodies& b, const BondChanges& changes, const std::vector<Made>& made);

  std::unique_ptr<Scratch> s_;
  uint64_t searched_ = 0;
  std::vector<sim::ModuleId> reframed_;
};

}  // namespace dw::physics
