// The static lattices an ensemble is laid out on: where each module sits and who touches whom.
// Module ids run x-fastest: x + nx * (y + ny * z).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sim/neighbor_graph.h"

namespace dw::sim {

enum class LatticeKind { Cubic, Square2d, Hex2d, Ring, Line, Fcc };

// "cubic", "square2d", "hex2d", "ring", "line", "fcc".
std::string_view lattice_name(LatticeKind kind);
std::optional<LatticeKind> lattice_from_name(std::string_view name);
// How many sizes a kind takes: 3 for cubic and fcc, 2 for the planar ones, 1 for ring and line.
int lattice_dimensions(LatticeKind kind);

struct LatticeSpec {
  LatticeKind kind = LatticeKind::Cubic;
  std::array<uint32_t, 3> size{1, 1, 1};  // unused dimensions are 1
  uint64_t module_count() const { return uint64_t{size[0]} * size[1] * size[2]; }
  bool operator==(const LatticeSpec&) const = default;
};

// The centre of module m's cell, one module size apart from the next; z is up. Computed, not
// kept: 12 bytes a module (12 MB for a 100^3 lattice) on every rank. Inline for the square
// grids, which the contact graph asks for every module's neighbours.
std::array<float, 3> cell_position_of_any_kind(const LatticeSpec& spec, ModuleId m);
// The same, from the cell's lattice coordinates, for every kind but the ring (whose cells are
// numbered around a circle).
inline std::array<float, 3> cell_centre(const LatticeSpec& spec, uint32_t x, uint32_t y, uint32_t z) {
  switch (spec.kind) {
    case LatticeKind::Hex2d:
      // Offset rows: odd rows shift half a module right, rows sqrt(3)/2 apart, so every module
      // touches six others (fewer at the border).
      return {float(x) + ((y & 1) ? 0.5f : 0.0f), float(y) * (std::sqrt(3.0f) / 2), 0};
    case LatticeKind::Fcc: {
      const float shift = (z & 1) ? 0.5f : 0.0f;
      return {float(x) + shift, float(y) + shift, float(z) * (std::sqrt(2.0f) / 2)};
    }
    default: return {float(x), float(y), float(z)};
  }
}
inline std::array<float, 3> cell_position(const LatticeSpec& spec, ModuleId m) {
  if (spec.kind != LatticeKind::Cubic && spec.kind != LatticeKind::Square2d) return cell_position_of_any_kind(spec, m);
  const uint32_t nx = spec.size[0], ny = spec.size[1], row = m / nx;
  return {float(m - row * nx), float(row % ny), float(row / ny)};
}

// The lattice coordinates (inclusive, x y z) of the cells whose centres may lie in the box
// [lo, hi]: every one that does, and at most a rounding's worth more. `empty` when there are none,
// and always for a ring, whose cells lie on a circle (its modules are few: callers list them).
struct CellRange {
  std::array<uint32_t, 3> from{}, to{};
  bool empty = true;
};
CellRange cells_in_box(const LatticeSpec& spec, const std::array<float, 3>& lo, const std::array<float, 3>& hi);
// Calls visit(m, centre) for every module of a lattice other than a ring whose cell's centre lies
// in the box [lo, hi], ascending: what a grid of module centres holds of those at rest, without
// holding them.
template <typename Visit>
void for_cells_in_box(const LatticeSpec& spec, const std::array<float, 3>& lo, const std::array<float, 3>& hi,
                      Visit&& visit) {
  const CellRange range = cells_in_box(spec, lo, hi);
  if (range.empty) return;
  const uint32_t nx = spec.size[0], ny = spec.size[1];
  for (uint32_t z = range.from[2]; z <= range.to[2]; ++z)
    for (uint32_t y = range.from[1]; y <= range.to[1]; ++y)
      for (uint32_t x = range.from[0]; x <= range.to[0]; ++x) {
        const std::array<float, 3> p = cell_centre(spec, x, y, z);
        if (p[0] >= lo[0] && p[0] <= hi[0] && p[1] >= lo[1] && p[1] <= hi[1] && p[2] >= lo[2] && p[2] <= hi[2])
          visit(x + nx * (y + ny * z), p);
      }
}

struct Lattice {
  LatticeSpec spec;
  std::array<float, 3> position(ModuleId m) const { return cell_position(spec, m); }
  std::vector<uint8_t> occupied;  // per cell: 0 for a cell left empty (no module there)
  // Face-adjacent modules; shared, not copied, by the states of a static lattice (the world's).
  // Null in a physical world's model, whose contacts make the graph: kept, it would be a second
  // one as large as the world's (lattice_graph makes it when asked).
  std::shared_ptr<const NeighborGraph> graph = std::make_shared<const NeighborGraph>();
};

// The lattice's face adjacency among its occupied cells: the graph it keeps, or one made afresh
// when it keeps none.
std::shared_ptr<const NeighborGraph> lattice_graph(const Lattice& lattice);

// fcc (face-centred cubic, Catoms 3D): square layers one on another, each odd layer shifted by
// half a module in x and y, layers sqrt(2)/2 apart, so that every module touches 12 others: 4
// in its layer (x +-1, y +-1), 4 in the layer above and 4 below (from an even layer at (x, y) the
// cells (x-1..x, y-1..y) of the odd layers; from an odd layer the cells (x..x+1, y..y+1)).
//
// Ring needs at least 3 modules; every size at least 1. The caller checks those (the scenario
// loader reports them against the file).
Lattice make_lattice(const LatticeSpec& spec);
// Leaves the cells of boxes (inclusive lattice coordinates, x y z, from and to) empty: their
// modules are absent for the whole run and touch nobody. Takes time in the boxes' number and the
// lattice's cells, however large the boxes are and however many overlap.
using LatticeBox = std::array<std::array<uint32_t, 3>, 2>;
void leave_empty(Lattice& lattice, std::span<const LatticeBox> boxes);
inline void leave_empty(Lattice& lattice, std::array<uint32_t, 3> from, std::array<uint32_t, 3> to) {
  const LatticeBox box{from, to};
  leave_empty(lattice, std::span(&box, 1));
}

}  // namespace dw::sim
