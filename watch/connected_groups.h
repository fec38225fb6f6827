// Every connected group of k modules, each exactly once (docs/design.md §4a, shape `any`): the ESU
// algorithm (Wernicke, "Efficient detection of network motifs", 2006). A group grows from its
// smallest module v only by modules greater than v that are *exclusive* neighbours of the module
// just added (adjacent to no module already in the group or beside it), so that no set of modules
// is reached by two orders. It enumerates sets, never ordered sequences: nothing is de-duplicated.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "watch/step_view.h"

namespace dw::watch {

// Whether some member of `group` reaches every other over the recorded (directed) edges within it.
bool rooted(const StepHistory::Graph& graph, std::span<const uint32_t> group);

// The graph among some modules with every recorded edge both ways, no repeats, no self-links.
class UndirectedGraph {
 public:
  // Returns whether the recorded graph among them already went both ways.
  bool build(const StepHistory::Graph& graph, std::span<const uint8_t> among);
  std::span<const uint32_t> neighbors(uint32_t m) const {
    return {ids_.data() + begin_[m], ids_.data() + begin_[m + 1]};
  }
  uint32_t module_count() const { return static_cast<uint32_t>(begin_.size() - 1); }
  size_t bytes() const { return (begin_.capacity() + ids_.capacity()) * sizeof(uint32_t) + pairs_.capacity() * 8; }

 private:
  std::vector<uint32_t> begin_, ids_;
  std::vector<std::pair<uint32_t, uint32_t>> pairs_;
};

class ConnectedGroups {
 public:
  explicit ConnectedGroups(uint32_t modules) : closed_(modules, 0) {}

  // Calls fn(group) for every set of k modules with eligible[m] that is connected in `graph` at
  // step t: some order of it has each module after the first in N(an earlier one) (over a
  // directed graph that is the same as a root reaching every member; over an undirected one,
  // plain connectivity). `group` lists the modules in the order they joined. fn returns whether
  // to go on. `budget` (0: none) bounds the groups grown, whole or partial: the number of
  // connected groups grows exponentially with k, and a watchpoint of 12 slots over a 6^3 lattice
  // enumerated for hours. Whether every group was reached (false: stopped by fn or the budget).
  template <class Fn>
  bool enumerate(const StepHistory::Graph& graph, std::span<const uint8_t> eligible, uint32_t k, Fn&& fn,
                 uint64_t budget = 0);

 private:
  template <class Fn>
  void grow(std::vector<uint32_t>& ext, uint32_t root, uint32_t k, const StepHistory::Graph& graph, Fn& fn);
  std::span<const uint32_t> adjacent(uint32_t m) const { return undirected_.neighbors(m); }

  UndirectedGraph undirected_;    // the graph among eligible modules
  bool symmetric_ = true;         // every edge among them goes both ways
  std::vector<uint32_t> closed_;  // [module]: members it is, or is beside
  std::vector<uint32_t> group_;
  std::vector<std::vector<uint32_t>> ext_;  // the extension set at each depth
  uint64_t grown_ = 0, budget_ = 0;         // groups grown this enumeration, and the most it may
  bool stopped_ = false;
  // Counts a group grown by one member: false when that is past the budget.
  bool count() { return !(stopped_ = stopped_ || (budget_ != 0 && ++grown_ > budget_)); }
};

template <class Fn>
bool ConnectedGroups::enumerate(const StepHistory::Graph& graph, std::span<const uint8_t> eligible, uint32_t k, Fn&& fn,
                                uint64_t budget) {
  if (k == 0) return true;
  grown_ = 0;
  budget_ = budget;
  stopped_ = false;
  symmetric_ = undirected_.build(graph, eligible);
  ext_.resize(k + 1);
  const uint32_t modules = undirected_.module_count();
  if (closed_.size() < modules) closed_.assign(modules, 0);
  for (uint32_t v = 0; v < modules; ++v) {
    if (!eligible[v]) continue;
    group_.assign(1, v);
    if (!count()) return false;
    if (k == 1) {
      if (!fn(std::span<const uint32_t>(group_))) return false;
      continue;
    }
    std::vector<uint32_t>& ext = ext_[1];
    ext.clear();
    ++closed_[v];
    for (uint32_t u : adjacent(v)) {
      ++closed_[u];
      if (u > v) ext.push_back(u);
    }
    grow(ext, v, k, graph, fn);
    --closed_[v];
    for (uint32_t u : adjacent(v)) --closed_[u];
    if (stopped_) return false;
  }
  return true;
}

template <class Fn>
void ConnectedGroups::grow(std::vector<uint32_t>& ext, uint32_t root, uint32_t k, const StepHistory::Graph& graph,
                           Fn& fn) {
  const size_t depth = group_.size();
  if (depth + 1 == k) {  // the last member: every module left in the extension set completes a group
    for (uint32_t w : ext) {
      if (!count()) return;
      group_.push_back(w);
      if ((symmetric_ || rooted(graph, group_)) && !fn(std::span<const uint32_t>(group_))) stopped_ = true;
      group_.pop_back();
      if (stopped_) return;
    }
    return;
  }
  std::vector<uint32_t>& next = ext_[depth + 1];
  for (size_t i = 0; i < ext.size(); ++i) {
    const uint32_t w = ext[i];
    if (!count()) return;
    next.assign(ext.begin() + static_cast<ptrdiff_t>(i) + 1, ext.end());
    for (uint32_t u : adjacent(w))
      if (u > root && closed_[u] == 0) next.push_back(u);
    ++closed_[w];
    for (uint32_t u : adjacent(w)) ++closed_[u];
    group_.push_back(w);
    grow(next, root, k, graph, fn);
    group_.pop_back();
    --closed_[w];
    for (uint32_t u : adjacent(w)) --closed_[u];
    if (stopped_) return;
  }
}

}  // namespace dw::watch
