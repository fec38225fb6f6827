// Who an aggregate ranges over beyond a module's own neighbours (docs/design.md §4c): the modules
// within h hops of it, found breadth-first over the neighbour lists of one step, as every reading
// reads them (from the whole ensemble's history, or from the history the engine keeps for agents),
// and the connected cluster of component(m: c) as it grows.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

namespace dw::watch {

// The modules present at 1..hops hops from `root` (itself excluded, even when it lists itself),
// following N(·) outward: each_neighbor(m, visit) calls visit(u) for every u in N(m), present(u)
// says whether u is present. Sorted by index into `out`; `seen` and `frontier` are scratch.
template <class EachNeighbor, class Present>
void gather_within(uint32_t root, int hops, EachNeighbor&& each_neighbor, Present&& present, std::vector<uint32_t>& out,
                   std::vector<uint32_t>& seen, std::vector<uint32_t>& frontier) {
  out.clear();
  seen.assign(1, root);  // sorted: a member's membership is one binary search
  frontier.assign(1, root);
  std::vector<uint32_t> next;
  for (int h = 0; h < hops && !frontier.empty(); ++h) {
    next.clear();
    for (uint32_t m : frontier)
      each_neighbor(m, [&](uint32_t u) {
        const auto at = std::lower_bound(seen.begin(), seen.end(), u);
        if ((at != seen.end() && *at == u) || !present(u)) return;
        seen.insert(at, u);
        next.push_back(u);
        out.push_back(u);
      });
    frontier.swap(next);
  }
  std::sort(out.begin(), out.end());
}

// component(m: c) as it grows (docs/design.md §4c): the present neighbours of `m`, a member, not yet
// in `seen` (sorted) become candidates at the end of `list`. Returns the list's size.
template <class EachNeighbor, class Present>
int add_candidates(uint32_t m, EachNeighbor&& each_neighbor, Present&& present, std::vector<uint32_t>& list,
                   std::vector<uint32_t>& seen) {
  each_neighbor(m, [&](uint32_t u) {
    const auto at = std::lower_bound(seen.begin(), seen.end(), u);
    if ((at != seen.end() && *at == u) || !present(u)) return;
    seen.insert(at, u);
    list.push_back(u);
  });
  return static_cast<int>(list.size());
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
