// A test's cube of boxes one module apart, each latched to the boxes it shares a face with (and,
// anchored, the bottom layer to the ground), its clusters formed.
#pragma once

#include <cmath>

#include "physics/clusters.h"
#include "sim/bodies.h"

namespace dw::physics::test {

inline sim::Bodies latched_block(int side, bool anchored, btCollisionShape& module_shape) {
  sim::Bodies b;
  const auto cells = static_cast<uint32_t>(side);
  const sim::LatticeSpec lattice{sim::LatticeKind::Cubic, {cells, cells, cells}};
  b.poses = decltype(b.poses)(sim::CellPose{lattice, 1});
  b.poses.resize(cells * cells * cells);  // each at its cell
  const auto n = static_cast<sim::ModuleId>(b.poses.size());
  b.velocities.resize(n);
  b.local.resize(n);
  // Latched to every lattice neighbour by default, as a world latches its lattice; those found
  // from the poses are put in too (they are the same: tests/sim/bond_set_test.cpp).
  b.bonds = sim::BondSet(lattice, true, n);
  for (sim::ModuleId m = 0; m < n; ++m) {
    for (sim::ModuleId o = m + 1; o < n; ++o) {
      const auto& p = b.poses[m].position;
      const auto& q = b.poses[o].position;
      if (std::abs(p[0] - q[0]) + std::abs(p[1] - q[1]) + std::abs(p[2] - q[2]) == 1) b.bonds.insert({m, o});
    }
    if (anchored && b.poses[m].position[2] == 0) b.bonds.insert({m, sim::kGround});
  }
  form_clusters(b, std::vector<uint8_t>(n, 1), module_shape);
  return b;
}

// Moves module m by `by` (the bodies keep poses by set()).
inline void shift(sim::Bodies& b, sim::ModuleId m, const sim::Vec3& by) {
  sim::Pose p = b.poses[m];
  for (int i = 0; i < 3; ++i) p.position[i] += by[i];
  b.poses.set(m, p);
}

}  // namespace dw::physics::test
