#include "physics/cell_grid.h"

#include <algorithm>
#include <cmath>

namespace dw::physics {

CellGrid::Cell CellGrid::cell(const sim::Vec3& at) const {
  const auto axis = [&](float v) {
    const double x = std::floor(double(v) / double(side_));
    if (!(x > double(-kReach))) return -kReach;  // NaN too
    if (x > double(kReach)) return kReach;
    return static_cast<int64_t>(x);
  };
  return {axis(at[0]), axis(at[1]), axis(at[2])};
}

void CellGrid::erase(sim::ModuleId m, const sim::Vec3& at) {
  const auto it = cells_.find(key(at));
  if (it == cells_.end()) return;
  std::vector<sim::ModuleId>& in = it->second;
  const auto at_m = std::find(in.begin(), in.end(), m);
  if (at_m == in.end()) return;
  *at_m = in.back();
  in.pop_back();
  if (in.empty()) cells_.erase(it);
}

void CellGrid::move(sim::ModuleId m, const sim::Vec3& from, const sim::Vec3& to) {
  if (key(from) == key(to)) return;
  erase(m, from);
  insert(m, to);
}

}  // namespace dw::physics
