// The root of x in a union-find forest over ids (parent[x] == x at a root), halving the path on
// the way: what clusters, regrouping and islands join things with.
#pragma once

#include <cstdint>
#include <vector>

namespace dw::physics {

inline uint32_t find_root(std::vector<uint32_t>& parent, uint32_t x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

}  // namespace dw::physics
