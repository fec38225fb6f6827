// The broadphase for bodies all of one size (docs/design.md §8): module centres binned in cubic
// cells of one side, so that every module whose centre lies within that side of a point is in
// the 27 cells around the point's own. Bullet's tree broadphase keeps a node per object and a
// hashed pair per overlap (13 per module in a lattice); for a million equal modules, a grid of
// their centres is what a uniform lattice asks for: a few bytes per module, and a module that
// moves is taken out of one cell and put in another.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "sim/bodies.h"

namespace dw::physics {

class CellGrid {
 public:
  explicit CellGrid(float side) : side_(side) {}

  float side() const { return side_; }
  void clear() { cells_.clear(); }
  void insert(sim::ModuleId m, const sim::Vec3& at) { cells_[key(at)].push_back(m); }
  // `at` is where the module was inserted or last moved to.
  void erase(sim::ModuleId m, const sim::Vec3& at);
  void move(sim::ModuleId m, const sim::Vec3& from, const sim::Vec3& to);

  // The number of cells a box [lo, hi] overlaps, and (within) calls visit(m) for every module
  // in them: all of those whose centres lie in the box, and others.
  uint64_t cells_in(const sim::Vec3& lo, const sim::Vec3& hi) const {
    const Cell a = cell(lo), b = cell(hi);
    return uint64_t(b.x - a.x + 1) * uint64_t(b.y - a.y + 1) * uint64_t(b.z - a.z + 1);
  }
  template <typename Visit>
  void within(const sim::Vec3& lo, const sim::Vec3& hi, Visit&& visit) const {
    const Cell a = cell(lo), b = cell(hi);
    for (int64_t z = a.z; z <= b.z; ++z)
      for (int64_t y = a.y; y <= b.y; ++y)
        for (int64_t x = a.x; x <= b.x; ++x) {
          const auto it = cells_.find(pack({x, y, z}));
          if (it == cells_.end()) continue;
          for (sim::ModuleId m : it->second) visit(m);
        }
  }

  // Calls visit(m) for every module in the 27 cells around `at`: all of those within side() of
  // it, and others (the caller measures).
  template <typename Visit>
  void around(const sim::Vec3& at, Visit&& visit) const {
    const Cell c = cell(at);
    for (int64_t dz = -1; dz <= 1; ++dz)
      for (int64_t dy = -1; dy <= 1; ++dy)
        for (int64_t dx = -1; dx <= 1; ++dx) {
          const auto it = cells_.find(pack({c.x + dx, c.y + dy, c.z + dz}));
          if (it == cells_.end()) continue;
          for (sim::ModuleId m : it->second) visit(m);
        }
  }

 private:
  struct Cell {
    int64_t x, y, z;
  };
  // Coordinates far out (a module flung away, or not finite) share the outermost cells: still
  // correct, since callers measure what they visit.
  static constexpr int64_t kReach = (int64_t{1} << 20) - 2;
  Cell cell(const sim::Vec3& at) const;
  static uint64_t pack(const Cell& c) {
    const auto field = [](int64_t v) { return static_cast<uint64_t>(v + (int64_t{1} << 20)) & 0x1fffff; };
    return field(c.x) | field(c.y) << 21 | field(c.z) << 42;
  }
  uint64_t key(const sim::Vec3& at) const { return pack(cell(at)); }

  float side_;
  std::unordered_map<uint64_t, std::vector<sim::ModuleId>> cells_;
};

}  // namespace dw::physics
