// N(m, t) for every module at one step, in compressed-row form: the neighbours of m are
// ids[begin[m] .. begin[m + 1]), sorted by id. Immutable once built, so states that share a
// topology (every step of a static lattice) share one graph.
//
// Over ranks a physical world's graph is a rank's *window* (docs/design.md §12a): it holds the
// lists of the modules the rank owns and of those within reach of them, each whole; the others'
// lists are empty. `held` says which are held.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace dw::sim {

using ModuleId = uint32_t;

struct NeighborGraph {
  std::vector<uint32_t> begin{0};  // [module_count + 1]
  std::vector<ModuleId> ids;
  std::shared_ptr<const std::vector<uint8_t>> held;  // per module: its list is held; null: every module's

  bool holds(ModuleId m) const { return !held || (*held)[m] != 0; }

  uint32_t module_count() const { return static_cast<uint32_t>(begin.size() - 1); }
  std::span<const ModuleId> neighbors(ModuleId m) const { return {ids.data() + begin[m], ids.data() + begin[m + 1]}; }
  bool adjacent(ModuleId a, ModuleId b) const;
  uint64_t edge_count() const { return ids.size(); }  // directed

  // Builds a symmetric graph from undirected pairs; each list comes out sorted, duplicates removed.
  static NeighborGraph from_pairs(uint32_t module_count, std::span<const std::pair<ModuleId, ModuleId>> pairs);
  // The same graph with module m cut out of it: no neighbours of its own, in nobody's list.
  NeighborGraph without(ModuleId m) const;
  // The same graph with the pairs `gone` taken out and `made` put in (each sorted, a < b; every
  // pair gone in it, none made): only the lists of their modules are rebuilt, the rest copied
  // (a million modules of which a thousand moved are not sorted again). `window`, when given, is
  // what the result holds, otherwise what this graph holds: the pairs change the lists held in
  // both; a list the window gained is `gained`'s (module, partner) entries (sorted), one it lost
  // comes out empty.
  NeighborGraph changed(std::span<const std::pair<ModuleId, ModuleId>> gone,
                        std::span<const std::pair<ModuleId, ModuleId>> made,
                        std::shared_ptr<const std::vector<uint8_t>> window = nullptr,
                        std::span<const std::pair<ModuleId, ModuleId>> gained = {}) const;
  // The same graph holding only the lists of the modules `window` holds: the others come out empty.
  NeighborGraph held_only(std::shared_ptr<const std::vector<uint8_t>> window) &&;
};

}  // namespace dw::sim
