// Islands: the bodies of a step that cannot touch each other within it, apart (issue: islands in
// parallel). Each body is given the box it can reach over the step (where it is, grown by how far
// it can move and turn); bodies whose boxes overlap, directly or through others, are one island.
// Each island is stepped in a Bullet world with the fixed and kinematic bodies near it (runs of
// small islands share one: physics/dynamics.cpp), so islands can be stepped on any thread in any
// order and give the same bits: the split is a function of the state, never of the thread count.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace dw::physics {

struct ReachBox {
  std::array<float, 3> lo{}, hi{};
  bool overlaps(const ReachBox& o) const {
    for (int i = 0; i < 3; ++i)
      if (hi[i] < o.lo[i] || o.hi[i] < lo[i]) return false;
    return true;
  }
  void cover(const ReachBox& o) {
    for (int i = 0; i < 3; ++i) {
      lo[i] = std::min(lo[i], o.lo[i]);
      hi[i] = std::max(hi[i], o.hi[i]);
    }
  }
};

// The island of each box: boxes overlapping directly or through others share one. Islands are
// numbered in the order of their first box.
std::vector<uint32_t> islands_of(std::span<const ReachBox> boxes, uint32_t& count);

// The islands each of `ranks` ranks steps (docs/design.md §12): runs in island order, of about equal
// total weight (an island's cost), rank r's from first[r] to first[r + 1]. A function of the
// weights alone, so every rank divides alike.
std::vector<uint32_t> rank_runs(std::span<const uint64_t> weight, uint32_t ranks);

}  // namespace dw::physics
