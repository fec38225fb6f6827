// A test's cube of boxes one module apart, each latched to the boxes it shares a face with (and,
// anchored, the bottom layer to the ground), its clusters formed.
#pragma once

#include <algorithm>
#include <cmath>

#include "physics/clusters.h"
#include "sim/bodies.h"

namespace dw::physics::test {

inline sim::Bodies latched_block(int side, bool anchored, btCollisionShape& module_shape) {
  sim::Bodies b;
  for (int z = 0; z < side; ++z)
    for (int y = 0; y < side; ++y)
      for (int x = 0; x < side; ++x) b.poses.push_back({.position = {float(x), float(y), float(z)}});
  const auto n = static_cast<sim::ModuleId>(b.poses.size());
  b.velocities.resize(n);
  b.local.resize(n);
  for (sim::ModuleId m = 0; m < n; ++m) {
    for (sim::ModuleId o = m + 1; o < n; ++o) {
      const auto& p = b.poses[m].position;
      const auto& q = b.poses[o].position;
      if (std::abs(p[0] - q[0]) + std::abs(p[1] - q[1]) + std::abs(p[2] - q[2]) == 1) b.bonds.push_back({m, o});
    }
    if (anchored && b.poses[m].position[2] == 0) b.bonds.push_back({m, sim::kGround});
  }
  std::sort(b.bonds.begin(), b.bonds.end());
  form_clusters(b, std::vector<uint8_t>(n, 1), module_shape);
  return b;
}

}  // namespace dw::physics::test
