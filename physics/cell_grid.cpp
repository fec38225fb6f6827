#include "physics/cell_grid.h"

#include <algorithm>
#include <cmath>

namespace dw::physics {

CellGrid::CellGrid(float side, const sim::CellPose& rest)
    : side_(side), at_cell_(rest.on_lattice && rest.lattice.kind != sim::LatticeKind::Ring), at_(CellCentre{rest}) {}

void CellGrid::resize(size_t n) {
  for (size_t m = n; m < state_.size(); ++m) place(static_cast<sim::ModuleId>(m), false, {});
  state_.resize(n, kOut);
  at_.resize(n);
}

CellGrid::Cell CellGrid::cell(const sim::Vec3& at) const {
  const auto axis = [&](float v) {
    const double x = std::floor(double(v) / double(side_));
    if (!(x > double(-kReach))) return -kReach;  // NaN too
    if (x > double(kReach)) return kReach;
    return static_cast<int64_t>(x);
  };
  return {axis(at[0]), axis(at[1]), axis(at[2])};
}

void CellGrid::unbin(sim::ModuleId m, const sim::Vec3& at) {
  const auto it = binned_.find(key(at));
  if (it == binned_.end()) return;
  std::vector<sim::ModuleId>& in = it->second;
  const auto at_m = std::find(in.begin(), in.end(), m);
  if (at_m == in.end()) return;
  *at_m = in.back();
  in.pop_back();
  if (in.empty()) binned_.erase(it);
}

void CellGrid::place(sim::ModuleId m, bool present, const sim::Vec3& at) {
  const State was = state_[m];
  State now = kOut;
  if (present) now = at_cell_ && at == at_.defaults()(m) ? kAtCell : kBinned;
  if (now == was && now != kBinned) return;
  const sim::Vec3 from = at_[m];
  // A binned module that moves within its grid cell stays in its bin.
  const bool rebin = was != now || key(from) != key(at);
  if (was == kBinned && rebin) unbin(m, from);
  if (now == kBinned && rebin) binned_[key(at)].push_back(m);
  binned_count_ += size_t(now == kBinned) - size_t(was == kBinned);
  state_[m] = now;
  if (now != kOut) at_.set(m, at);
}

}  // namespace dw::physics
