#include "physics/islands.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

#include "physics/union_find.h"

namespace dw::physics {

namespace {

// Joins the islands of boxes a and b when they overlap.
void join_if_overlapping(std::span<const ReachBox> boxes, std::vector<uint32_t>& parent, uint32_t a, uint32_t b) {
  if (!boxes[a].overlaps(boxes[b])) return;
  const uint32_t ra = find_root(parent, a), rb = find_root(parent, b);
  parent[std::max(ra, rb)] = std::min(ra, rb);
}

// The box's widest side; infinite for a box that is not finite (it then goes with the wide ones).
float extent(const ReachBox& box) {
  const float e = std::max({box.hi[0] - box.lo[0], box.hi[1] - box.lo[1], box.hi[2] - box.lo[2]});
  return std::isfinite(e) ? e : std::numeric_limits<float>::infinity();
}

}  // namespace

std::vector<uint32_t> islands_of(std::span<const ReachBox> boxes, uint32_t& count) {
  const auto n = static_cast<uint32_t>(boxes.size());
  std::vector<uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  // Candidates from a grid whose cells are as wide as three boxes in four are: each box is entered
  // in every cell it covers, so two boxes that overlap share one. A box covering more than
  // kMostCells cells (a large bonded cluster, a prop) is tested against every box instead. A sweep
  // along one axis, as before, tested each box of a lattice against its whole slab.
  constexpr uint64_t kMostCells = 64;
  std::vector<float> extents(n);
  for (uint32_t i = 0; i < n; ++i) extents[i] = extent(boxes[i]);
  float cell = 0;
  if (n > 0) {
    const size_t quantile = size_t(n) * 3 / 4;
    std::nth_element(extents.begin(), extents.begin() + ptrdiff_t(quantile), extents.end());
    cell = extents[quantile];
  }
  std::array<float, 3> origin{};
  for (uint32_t i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) origin[a] = i == 0 ? boxes[i].lo[a] : std::min(origin[a], boxes[i].lo[a]);
  std::vector<uint32_t> wide;
  std::vector<std::pair<uint64_t, uint32_t>> entries;  // (cell key, box)
  entries.reserve(size_t(n) * 8);
  for (uint32_t i = 0; i < n; ++i) {
    // The cells covered along each axis, when they are few and the box is finite.
    std::array<uint64_t, 3> lo{}, hi{};
    uint64_t cells = 1;
    for (int a = 0; a < 3 && cells <= kMostCells; ++a) {
      const float from = (boxes[i].lo[a] - origin[a]) / cell, to = (boxes[i].hi[a] - origin[a]) / cell;
      if (!(from >= 0 && to >= from && to < float(1 << 20))) {
        cells = kMostCells + 1;
        break;
      }
      lo[a] = uint64_t(from);
      hi[a] = uint64_t(to);
      cells *= hi[a] - lo[a] + 1;
    }
    if (cells > kMostCells) {
      wide.push_back(i);
      continue;
    }
    for (uint64_t x = lo[0]; x <= hi[0]; ++x)
      for (uint64_t y = lo[1]; y <= hi[1]; ++y)
        for (uint64_t z = lo[2]; z <= hi[2]; ++z) entries.emplace_back(x << 40 | y << 20 | z, i);
  }
  std::sort(entries.begin(), entries.end());
  for (size_t from = 0; from < entries.size();) {
    size_t to = from + 1;
    while (to < entries.size() && entries[to].first == entries[from].first) ++to;
    for (size_t j = from; j < to; ++j)
      for (size_t k = j + 1; k < to; ++k) join_if_overlapping(boxes, parent, entries[j].second, entries[k].second);
    from = to;
  }
  for (uint32_t w : wide)
    for (uint32_t i = 0; i < n; ++i)
      if (i != w) join_if_overlapping(boxes, parent, w, i);

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
