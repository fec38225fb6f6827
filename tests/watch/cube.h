// The Table I ensemble's lattice for exact-count tests: an n x n x n cube, 6-connected.
#pragma once

#include "test_ensemble.h"

namespace dw::watch::testing {

inline std::vector<std::vector<uint32_t>> cube_neighbors(uint32_t n) {
  std::vector<std::vector<uint32_t>> nbrs(n * n * n);
  auto id = [n](uint32_t x, uint32_t y, uint32_t z) { return (z * n + y) * n + x; };
  for (uint32_t z = 0; z < n; ++z)
    for (uint32_t y = 0; y < n; ++y)
      for (uint32_t x = 0; x < n; ++x) {
        auto& l = nbrs[id(x, y, z)];
        if (x > 0) l.push_back(id(x - 1, y, z));
        if (x + 1 < n) l.push_back(id(x + 1, y, z));
        if (y > 0) l.push_back(id(x, y - 1, z));
        if (y + 1 < n) l.push_back(id(x, y + 1, z));
        if (z > 0) l.push_back(id(x, y, z - 1));
        if (z + 1 < n) l.push_back(id(x, y, z + 1));
      }
  return nbrs;
}

// The cube for `steps` steps, every module with x = 0.
inline TestEnsemble cube_ensemble(uint32_t n, int64_t steps) {
  const auto nbrs = cube_neighbors(n);
  TestEnsemble e(n * n * n, {"x"});
  for (int64_t t = 0; t < steps; ++t)
    for (uint32_t m = 0; m < n * n * n; ++m) e.set(t, m, {{"x", 0}}, nbrs[m]);
  return e;
}

}  // namespace dw::watch::testing
