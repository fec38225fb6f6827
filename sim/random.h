// Counter-based randomness (docs/design.md §2): a number is a pure function of (seed, module, step,
// stream), so neither the order in which modules run nor the thread count can change it.
#pragma once

#include <cstdint>

namespace dw::sim {

inline uint64_t counter_random(uint64_t seed, uint64_t module, uint64_t step, uint64_t stream) {
  // splitmix64's finalizer over a mix of the counters.
  uint64_t z = seed * 0x9E3779B97F4A7C15ull ^ module * 0xBF58476D1CE4E5B9ull ^ step * 0x94D049BB133111EBull ^
               (stream + 1) * 0xD6E8FEB86659FD93ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace dw::sim
