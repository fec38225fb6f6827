// N(m, t) for every module at one step, in compressed-row form: the neighbours of m are
// ids[begin[m] .. begin[m + 1]), sorted by id. Immutable once built, so states that share a
// topology (every step of a static lattice) share one graph.
#pragma once

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace dw::sim {

using ModuleId = uint32_t;

struct NeighborGraph {
  std::vector<uint32_t> begin{0};  // [module_count + 1]
  std::vector<ModuleId> ids;

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
  // (a million modules of which a thousand moved are not sorted again).
  NeighborGraph changed(std::span<const std::pair<ModuleId, ModuleId>> gone,
                        std::span<const std::pair<ModuleId, ModuleId>> made) const;
};

}  // namespace dw::sim
