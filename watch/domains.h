// Who an aggregate ranges over beyond a module's own neighbours (docs/design.md §4c): the modules
// within h hops of it, found breadth-first over the neighbour lists of one step, as every reading
// reads them (from the whole ensemble's history, or from the history the engine keeps for agents),
// and the connected cluster of component(m: c) as it grows.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

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
