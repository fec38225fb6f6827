#include "sim/neighbor_graph.h"

#include <algorithm>

namespace dw::sim {

bool NeighborGraph::adjacent(ModuleId a, ModuleId b) const {
  const auto n = neighbors(a);
  return std::binary_search(n.begin(), n.end(), b);
}

NeighborGraph NeighborGraph::without(ModuleId gone) const {
  NeighborGraph g;
  g.held = held;
  g.begin.assign(begin.size(), 0);
  g.ids.reserve(ids.size());
  for (ModuleId m = 0; m < module_count(); ++m) {
    if (m != gone)
      for (ModuleId n : neighbors(m))
        if (n != gone) g.ids.push_back(n);
    g.begin[m + 1] = static_cast<uint32_t>(g.ids.size());
  }
  return g;
}

NeighborGraph NeighborGraph::from_pairs(uint32_t module_count, std::span<const std::pair<ModuleId, ModuleId>> pairs) {
  NeighborGraph g;
  std::vector<uint32_t> degree(module_count + 1, 0);
  for (const auto& [a, b] : pairs) {
    ++degree[a];
    ++degree[b];
  }
  g.begin.assign(module_count + 1, 0);
  for (uint32_t m = 0; m < module_count; ++m) g.begin[m + 1] = g.begin[m] + degree[m];
  g.ids.resize(g.begin[module_count]);
  std::vector<uint32_t> fill(g.begin.begin(), g.begin.end() - 1);
  for (const auto& [a, b] : pairs) {
    g.ids[fill[a]++] = b;
    g.ids[fill[b]++] = a;
  }
  // Pairs sorted and each a < b (the contact graph's): every list came out sorted already, its
  // smaller ids (from pairs ending in it) before its larger ones.
  const auto in_order = [](const auto& x, const auto& y) { return x.first < x.second && x < y; };
  if (std::adjacent_find(pairs.begin(), pairs.end(), [&](const auto& x, const auto& y) { return !in_order(x, y); }) ==
          pairs.end() &&
      (pairs.empty() || pairs.back().first < pairs.back().second))
    return g;
  // Sort each list and drop duplicates, compacting in place.
  uint32_t out = 0;
  for (uint32_t m = 0; m < module_count; ++m) {
    auto first = g.ids.begin() + g.begin[m];
    auto last = g.ids.begin() + g.begin[m + 1];
    std::sort(first, last);
    last = std::unique(first, last);
    g.begin[m] = out;
    for (auto it = first; it != last; ++it) g.ids[out++] = *it;
  }
  g.begin[module_count] = out;
  g.ids.resize(out);
  return g;
}

NeighborGraph NeighborGraph::changed(std::span<const std::pair<ModuleId, ModuleId>> gone,
                                     std::span<const std::pair<ModuleId, ModuleId>> made,
                                     std::shared_ptr<const std::vector<uint8_t>> window,
                                     std::span<const std::pair<ModuleId, ModuleId>> gained) const {
  NeighborGraph g;
  g.held = window ? std::move(window) : held;
  // Per module touched, its partners gone or made: (module, partner, made?), sorted by module.
  struct Change {
    ModuleId module, partner;
    bool made;
    bool operator<(const Change& o) const { return module < o.module || (module == o.module && partner < o.partner); }
  };
  std::vector<Change> changes;
  const auto change = [&](ModuleId m, ModuleId partner, bool made) {
    if (g.holds(m) && holds(m)) changes.push_back({m, partner, made});
  };
  for (const auto& [a, b] : gone) change(a, b, false), change(b, a, false);
  for (const auto& [a, b] : made) change(a, b, true), change(b, a, true);
  for (const auto& [m, partner] : gained) changes.push_back({m, partner, true});  // into an empty list
  std::sort(changes.begin(), changes.end());

  const uint32_t n = module_count();
  g.begin.resize(begin.size());
  g.ids.reserve(ids.size() + made.size() * 2);
  uint32_t copied = 0;  // modules before this one are in g
  for (size_t i = 0; i < changes.size();) {
    const ModuleId m = changes[i].module;
    // The untouched modules before m: their lists as they were, shifted.
    const auto shift = static_cast<int64_t>(g.ids.size()) - begin[copied];
    for (uint32_t k = copied; k < m; ++k) g.begin[k] = static_cast<uint32_t>(begin[k] + shift);
    g.ids.insert(g.ids.end(), ids.begin() + begin[copied], ids.begin() + begin[m]);
    // m's list: the old one without what went, merged with what came (both sorted).
    g.begin[m] = static_cast<uint32_t>(g.ids.size());
    size_t j = i;
    while (j < changes.size() && changes[j].module == m) ++j;
    const std::span<const ModuleId> old = neighbors(m);
    auto next = changes.begin() + ptrdiff_t(i);
    const auto end = changes.begin() + ptrdiff_t(j);
    for (ModuleId o : old) {
      for (; next != end && next->partner < o; ++next)
        if (next->made) g.ids.push_back(next->partner);
      if (next != end && next->partner == o) {  // gone
        ++next;
        continue;
      }
      g.ids.push_back(o);
    }
    for (; next != end; ++next)
      if (next->made) g.ids.push_back(next->partner);
    copied = m + 1;
    i = j;
  }
  const auto shift = static_cast<int64_t>(g.ids.size()) - begin[copied];
  for (uint32_t k = copied; k <= n; ++k) g.begin[k] = static_cast<uint32_t>(begin[k] + shift);
  g.ids.insert(g.ids.end(), ids.begin() + begin[copied], ids.end());
  if (g.held == held) return g;
  // The lists of the modules the window lost go.
  std::shared_ptr<const std::vector<uint8_t>> kept = g.held;
  return std::move(g).held_only(std::move(kept));
}

NeighborGraph NeighborGraph::held_only(std::shared_ptr<const std::vector<uint8_t>> window) && {
  NeighborGraph g = std::move(*this);
  g.held = std::move(window);
  if (!g.held) return g;
  uint32_t out = 0;
  for (ModuleId m = 0; m < g.module_count(); ++m) {
    const uint32_t from = g.begin[m], to = g.begin[m + 1];
    g.begin[m] = out;
    if ((*g.held)[m])
      for (uint32_t e = from; e < to; ++e) g.ids[out++] = g.ids[e];
  }
  g.begin[g.module_count()] = out;
  g.ids.resize(out);
  g.ids.shrink_to_fit();
  return g;
}

}  // namespace dw::sim
