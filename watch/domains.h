// Who an aggregate ranges over beyond a module's own neighbours (docs/design.md §4c): the modules
// within h hops of it, found breadth-first over the neighbour lists of one step, as every reading
// reads them (from the whole ensemble's history, or from the history the engine keeps for agents),
// and the connected cluster of component(m: c) as it grows; and the opening of every aggregate's
// domain (open_domain), shared by the three readings.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "watch/ast.h"

namespace dw::watch {

// The modules reached in one search, each marked with the search's generation: a new search
// clears every mark in O(1), and a membership is one load (not a binary search, nor an insert in
// the middle of a sorted list). Grows to the largest module index seen and is kept from call to
// call, so a search allocates nothing once warm.
class VisitMarks {
 public:
  void start() {
    if (++generation_ == 0) {  // wrapped: marks of 2^32 searches ago would read as this one's
      std::fill(marks_.begin(), marks_.end(), 0);
      generation_ = 1;
    }
  }
  // Marks u; whether it was not marked in this search yet.
  bool mark(uint32_t u) {
    if (u >= marks_.size()) marks_.resize(size_t{u} + 1 + u / 2, 0);
    if (marks_[u] == generation_) return false;
    marks_[u] = generation_;
    return true;
  }

 private:
  std::vector<uint32_t> marks_;
  uint32_t generation_ = 0;
};

// The present neighbours of `m` not reached yet in this search (`seen`) are reached: appended to
// `list`. each_neighbor(m, visit) calls visit(u) for every u in N(m), present(u) says whether u is
// present. Returns the list's size. component(m: c) grows this way (docs/design.md §4c), and so
// does within's breadth-first search.
template <class EachNeighbor, class Present>
int add_candidates(uint32_t m, EachNeighbor&& each_neighbor, Present&& present, std::vector<uint32_t>& list,
                   VisitMarks& seen) {
  each_neighbor(m, [&](uint32_t u) {
    if (present(u) && seen.mark(u)) list.push_back(u);
  });
  return static_cast<int>(list.size());
}

// The modules present at 1..hops hops from `root` (itself excluded, even when it lists itself),
// following N(·) outward, sorted by index into `out`. Breadth-first with `out` as its queue: each
// hop's modules follow the one before's.
template <class EachNeighbor, class Present>
void gather_within(uint32_t root, int hops, EachNeighbor&& each_neighbor, Present&& present, std::vector<uint32_t>& out,
                   VisitMarks& seen) {
  out.clear();
  seen.start();
  seen.mark(root);
  add_candidates(root, each_neighbor, present, out, seen);
  for (size_t begin = 0, end = out.size(), h = 1; h < static_cast<size_t>(hops) && begin < end; ++h) {
    for (size_t i = begin; i < end; ++i) add_candidates(out[i], each_neighbor, present, out, seen);
    begin = end;
    end = out.size();
  }
  std::sort(out.begin(), out.end());
}

// The domain an aggregate ranges over at one step. Written once, not once per reading (the whole
// ensemble's history for a step, the engine's history for agents, a recorded window for `why` and
// `find`), so that the three cannot drift apart: they must agree element for element and in
// order (docs/design.md §4b-§4c). Into `out`:
// - All: every present module of [first, end), by index;
// - Component: candidate 0, the root, alone in a fresh search of `seen`; the evaluator grows it;
// - Within: the ball of `hops` hops, as ball(root, gather) leaves it in `out` (gather(list) finds
//   it into `list`; a reading with a BallCache keeps it from step to step, another calls gather(out));
// - Neighbors: N(root) as a set of the present neighbours, by index.
// Returns the count, or -1 when the root (root_module(), asked for every domain but All) is absent.
// each_neighbor and present are as for add_candidates, at the step opened; the caller has checked
// that the step is held.
template <class RootModule, class EachNeighbor, class Present, class Ball>
int open_domain(Domain domain, int hops, RootModule&& root_module, uint32_t first, uint32_t end,
                EachNeighbor&& each_neighbor, Present&& present, Ball&& ball, std::vector<uint32_t>& out,
                VisitMarks& seen) {
  out.clear();
  if (domain == Domain::All) {
    for (uint32_t u = first; u < end; ++u)
      if (present(u)) out.push_back(u);
    return static_cast<int>(out.size());
  }
  const uint32_t root = root_module();
  if (!present(root)) return -1;
  if (domain == Domain::Component) {
    out.assign(1, root);
    seen.start();
    seen.mark(root);
    return 1;
  }
  if (domain == Domain::Within) {
    ball(root, [&](std::vector<uint32_t>& list) { gather_within(root, hops, each_neighbor, present, list, seen); });
    return static_cast<int>(out.size());
  }
  each_neighbor(root, [&](uint32_t u) {
    if (present(u)) out.push_back(u);
  });
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return static_cast<int>(out.size());
}

// Balls kept from step to step: within(m, h) is a function of the graph's links and presence
// alone, so while they stay the same (a lattice at rest: the whole run) each module's ball is
// searched once, not once a step and a reading. A graph is named by its version (the history's:
// equal versions, equal links and presence; 0 names none). One cache per within() aggregate, and
// its entries are written only by whoever evaluates their module: a thread that evaluates its own
// block's modules, or a thread's own cache.
class BallCache {
 public:
  // Root `index`'s ball over graph `version`, as gather(out) finds it when not kept yet. A ball
  // larger than kMostKept is found again every time (kept, a few such would outweigh the history).
  template <class Gather>
  std::span<const uint32_t> ball(uint32_t index, uint64_t version, Gather&& gather, std::vector<uint32_t>& scratch) {
    if (version == 0) {
      gather(scratch);
      return scratch;
    }
    if (index >= kept_.size()) kept_.resize(size_t{index} + 1 + index / 2);
    Kept& k = kept_[index];
    if (k.version == version) return k.ids;
    gather(scratch);
    if (scratch.size() > kMostKept) return scratch;
    k.ids.assign(scratch.begin(), scratch.end());
    k.version = version;
    return k.ids;
  }
  // Makes room for roots [0, roots) at once: a cache whose roots are evaluated by several threads
  // (each its own) must not grow while they run.
  void reserve(uint32_t roots) {
    if (kept_.size() < roots) kept_.resize(roots);
  }
  static constexpr size_t kMostKept = 1024;

 private:
  struct Kept {
    uint64_t version = 0;
    std::vector<uint32_t> ids;
  };
  std::vector<Kept> kept_;  // [root index]
};

// Keeps the candidates marked as members, sorted. Returns their count.
inline int keep_members(std::vector<uint32_t>& list, const std::vector<uint8_t>& joined) {
  size_t kept = 0;
  for (size_t i = 0; i < list.size(); ++i)
    if (i < joined.size() && joined[i]) list[kept++] = list[i];
  list.resize(kept);
  std::sort(list.begin(), list.end());
  return static_cast<int>(kept);
}

}  // namespace dw::watch
