// The broadphase for bodies all of one size (docs/design.md §8): module centres binned in cubic
// cells of one side, so that every module whose centre lies within that side of a point is in
// the 27 cells around the point's own. Bullet's tree broadphase keeps a node per object and a
// hashed pair per overlap (13 per module in a lattice); for a million equal modules, a grid of
// their centres is what a uniform lattice asks for, and a module that moves is taken out of one
// cell and put in another.
//
// A module at rest in its lattice cell (sim::CellPose) is not binned: the grid finds it from
// the lattice, by its cell's coordinates. Only the modules away from their cells are kept, so a
// still million-module lattice costs the grid a byte a module, where binning every one took 26.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "sim/bodies.h"
#include "sim/paged_array.h"

namespace dw::physics {

class CellGrid {
 public:
  // `rest`: where each module's cell is (none without a lattice: every module is binned).
  explicit CellGrid(float side, const sim::CellPose& rest = {});

  float side() const { return side_; }
  const sim::CellPose& rest() const { return at_.defaults().cell; }
  // Room for n modules; those added are out of the grid.
  void resize(size_t n);

  // Puts module m at `at`, or takes it out of the grid (not present).
  void place(sim::ModuleId m, bool present, const sim::Vec3& at);
  // Where module m was placed last (while in the grid).
  sim::Vec3 at(sim::ModuleId m) const { return at_[m]; }
  // How many modules are binned: those present away from their cells.
  size_t binned() const { return binned_count_; }

  // The number of cells a box [lo, hi] overlaps, and (within) calls visit(m, at) for every module
  // in them, with where it is: all of those whose centres lie in the box, and others.
  uint64_t cells_in(const sim::Vec3& lo, const sim::Vec3& hi) const {
    const Cell a = cell(lo), b = cell(hi);
    return uint64_t(b.x - a.x + 1) * uint64_t(b.y - a.y + 1) * uint64_t(b.z - a.z + 1);
  }
  template <typename Visit>
  void within(const sim::Vec3& lo, const sim::Vec3& hi, Visit&& visit) const {
    visit_binned(cell(lo), cell(hi), visit);
    visit_at_cells(lo, hi, visit);
  }
  // Calls visit(m, at) for every module within side() of `at`, and others (the caller measures):
  // those binned in the 27 cells around its own, and those at rest within side() of it on each
  // axis.
  template <typename Visit>
  void around(const sim::Vec3& at, Visit&& visit) const {
    const Cell c = cell(at);
    visit_binned({c.x - 1, c.y - 1, c.z - 1}, {c.x + 1, c.y + 1, c.z + 1}, visit);
    visit_at_cells({at[0] - side_, at[1] - side_, at[2] - side_}, {at[0] + side_, at[1] + side_, at[2] + side_}, visit);
  }

 private:
  struct Cell {
    int64_t x, y, z;
  };
  // Where a module at rest is: its cell's centre.
  struct CellCentre {
    sim::CellPose cell;
    sim::Vec3 operator()(size_t m) const { return cell(m).position; }
    bool operator==(const CellCentre&) const = default;
  };
  // Per module: out of the grid, at rest in its cell (found from the lattice), or binned.
  enum State : uint8_t { kOut, kAtCell, kBinned };

  // Calls visit(m, at) for the modules binned in the cells a to b (inclusive).
  template <typename Visit>
  void visit_binned(const Cell& a, const Cell& b, Visit& visit) const {
    if (binned_.empty()) return;
    for (int64_t z = a.z; z <= b.z; ++z)
      for (int64_t y = a.y; y <= b.y; ++y)
        for (int64_t x = a.x; x <= b.x; ++x) {
          const auto it = binned_.find(pack({x, y, z}));
          if (it == binned_.end()) continue;
          for (sim::ModuleId m : it->second) visit(m, at_[m]);
        }
  }
  // Calls visit(m, at) for the modules at rest in their cells whose centres lie in the box
  // [lo, hi]: the box itself, not the grid's cells around it, which would hold twice as many.
  template <typename Visit>
  void visit_at_cells(const sim::Vec3& lo, const sim::Vec3& hi, Visit& visit) const {
    if (!at_cell_) return;
    sim::for_cells_in_box(rest().lattice, lo, hi, [&](sim::ModuleId m, const sim::Vec3& centre) {
      if (m < state_.size() && state_[m] == kAtCell) visit(m, centre);
    });
  }

  // Coordinates far out (a module flung away, or not finite) share the outermost cells: still
  // correct, since callers measure what they visit.
  static constexpr int64_t kReach = (int64_t{1} << 20) - 2;
  Cell cell(const sim::Vec3& at) const;
  static uint64_t pack(const Cell& c) {
    const auto field = [](int64_t v) { return static_cast<uint64_t>(v + (int64_t{1} << 20)) & 0x1fffff; };
    return field(c.x) | field(c.y) << 21 | field(c.z) << 42;
  }
  uint64_t key(const sim::Vec3& at) const { return pack(cell(at)); }
  void unbin(sim::ModuleId m, const sim::Vec3& at);

  float side_;
  bool at_cell_;  // whether modules at rest are found from the lattice (not for a ring)
  std::vector<State> state_;
  sim::PagedArray<sim::Vec3, CellCentre> at_;  // a module at rest: its cell's centre, not kept
  std::unordered_map<uint64_t, std::vector<sim::ModuleId>> binned_;
  size_t binned_count_ = 0;
};

}  // namespace dw::physics
