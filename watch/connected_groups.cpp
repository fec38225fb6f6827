#include "watch/connected_groups.h"

#include <algorithm>

namespace dw::watch {

bool UndirectedGraph::build(const StepHistory::Graph& graph, std::span<const uint8_t> among) {
  const uint32_t modules = static_cast<uint32_t>(graph.present.size());
  pairs_.clear();
  for (uint32_t m = 0; m < modules; ++m) {
    if (!among[m]) continue;
    for (uint32_t n : graph.neighbors(m))
      if (n != m && n < modules && among[n]) pairs_.emplace_back(m, n);
  }
  std::sort(pairs_.begin(), pairs_.end());
  pairs_.erase(std::unique(pairs_.begin(), pairs_.end()), pairs_.end());
  const size_t directed = pairs_.size();
  for (size_t i = 0; i < directed; ++i) pairs_.emplace_back(pairs_[i].second, pairs_[i].first);
  std::sort(pairs_.begin(), pairs_.end());
  pairs_.erase(std::unique(pairs_.begin(), pairs_.end()), pairs_.end());
  begin_.assign(modules + 1, 0);
  for (const auto& p : pairs_) ++begin_[p.first + 1];
  for (uint32_t m = 0; m < modules; ++m) begin_[m + 1] += begin_[m];
  ids_.resize(pairs_.size());
  for (size_t i = 0; i < pairs_.size(); ++i) ids_[i] = pairs_[i].second;  // sorted by first: in place
  return pairs_.size() == directed;
}

bool rooted(const StepHistory::Graph& graph, std::span<const uint32_t> group) {
  const size_t k = group.size();
  const uint64_t all = k == 64 ? ~uint64_t{0} : (uint64_t{1} << k) - 1;
  for (size_t r = 0; r < k; ++r) {
    uint64_t reached = uint64_t{1} << r, frontier = reached;
    while (frontier) {
      uint64_t next = 0;
      for (size_t a = 0; a < k; ++a) {
        if (!(frontier >> a & 1)) continue;
        const auto n = graph.neighbors(group[a]);
        for (size_t b = 0; b < k; ++b)
          if (!(reached >> b & 1) && std::find(n.begin(), n.end(), group[b]) != n.end()) next |= uint64_t{1} << b;
      }
      reached |= next;
      frontier = next;
    }
    if (reached == all) return true;
  }
  return false;
}

}  // namespace dw::watch
