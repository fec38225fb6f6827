#include "sim/synthetic_trace.h"

#include <string>

namespace dw::sim {

Trace make_cubic_random_vars(const CubicRandomVars& s) {
  std::vector<std::string> names;
  for (size_t i = 0; i < s.maxima.size(); ++i) names.push_back("x" + std::to_string(i + 1));
  auto id = [&](uint32_t x, uint32_t y, uint32_t z) { return x + s.nx * (y + s.ny * z); };
  std::vector<Trace::Entry> entries;
  entries.reserve(static_cast<size_t>(s.steps) * s.nx * s.ny * s.nz);
  for (int64_t t = 0; t < s.steps; ++t)
    for (uint32_t z = 0; z < s.nz; ++z)
      for (uint32_t y = 0; y < s.ny; ++y)
        for (uint32_t x = 0; x < s.nx; ++x) {
          Trace::Entry e;
          e.t = t;
          e.m = id(x, y, z);
          for (size_t v = 0; v < s.maxima.size(); ++v)
            e.vars.emplace_back(static_cast<uint32_t>(v),
                                static_cast<int64_t>(counter_random(s.seed, e.m, static_cast<uint64_t>(t), v) %
                                                     static_cast<uint64_t>(s.maxima[v])));
          if (x > 0) e.nbrs.push_back(id(x - 1, y, z));
          if (x + 1 < s.nx) e.nbrs.push_back(id(x + 1, y, z));
          if (y > 0) e.nbrs.push_back(id(x, y - 1, z));
          if (y + 1 < s.ny) e.nbrs.push_back(id(x, y + 1, z));
          if (z > 0) e.nbrs.push_back(id(x, y, z - 1));
          if (z + 1 < s.nz) e.nbrs.push_back(id(x, y, z + 1));
          entries.push_back(std::move(e));
        }
  return Trace::build(std::move(entries), std::move(names));
}

}  // namespace dw::sim
