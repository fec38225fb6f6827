#include "physics/islands.h"

#include <algorithm>
#include <numeric>

#include "physics/union_find.h"

namespace dw::physics {

std::vector<uint32_t> islands_of(std::span<const ReachBox> boxes, uint32_t& count) {
  const auto n = static_cast<uint32_t>(boxes.size());
  std::vector<uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  // Sweep along x: each box against those that start before it and have not ended yet.
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return boxes[a].lo[0] < boxes[b].lo[0] || (boxes[a].lo[0] == boxes[b].lo[0] && a < b);
  });
  std::vector<uint32_t> open;
  for (uint32_t i : order) {
    std::erase_if(open, [&](uint32_t j) { return boxes[j].hi[0] < boxes[i].lo[0]; });
    for (uint32_t j : open)
      if (boxes[i].overlaps(boxes[j])) {
        const uint32_t a = find_root(parent, i), b = find_root(parent, j);
        parent[std::max(a, b)] = std::min(a, b);
      }
    open.push_back(i);
  }
  std::vector<uint32_t> island(n);
  count = 0;
  std::vector<uint32_t> number(n, UINT32_MAX);
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t r = find_root(parent, i);
    if (number[r] == UINT32_MAX) number[r] = count++;
    island[i] = number[r];
  }
  return island;
}

std::vector<uint32_t> rank_runs(std::span<const uint64_t> weight, uint32_t ranks) {
  // Each island goes to the rank its middle falls in, along the weights laid end to end.
  const uint64_t total = std::accumulate(weight.begin(), weight.end(), uint64_t{0});
  std::vector<uint32_t> first(ranks + 1, static_cast<uint32_t>(weight.size()));
  first[0] = 0;
  uint64_t before = 0;
  uint32_t rank = 0;
  for (uint32_t i = 0; i < weight.size(); ++i) {
    const uint64_t owner = std::min<uint64_t>(ranks - 1, ranks * (2 * before + weight[i]) / (2 * total));
    while (rank < owner) first[++rank] = i;
    before += weight[i];
  }
  return first;
}

}  // namespace dw::physics
