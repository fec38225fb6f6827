// Synthetic traces for benchmarks and tests: the paper's §V set-up, a cubic lattice whose
// modules draw x1..xk uniformly from 0..max_i-1 every step (the Table I host program).
#pragma once

#include <cstdint>
#include <vector>

#include "sim/random.h"
#include "sim/trace.h"

namespace dw::sim {

struct CubicRandomVars {
  uint32_t nx = 10, ny = 10, nz = 10;
  int64_t steps = 100;
  std::vector<int64_t> maxima{1, 1, 1, 1};  // the tuple [max_x1 : ... : max_xk]
  uint64_t seed = 1;
};

// Face-adjacent neighbours (6 in the interior), ids x + nx * (y + ny * z).
Trace make_cubic_random_vars(const CubicRandomVars& spec);

}  // namespace dw::sim
