// The static lattices an ensemble is laid out on: where each module sits and who touches whom.
// Module ids run x-fastest: x + nx * (y + ny * z).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sim/neighbor_graph.h"

namespace dw::sim {

// Hex2dVertical is hex2d stood up in the x-z plane (2-D catoms rolling against gravity): the same
// cells, ids and links as hex2d, its rows climbing along z instead of running along y.
enum class LatticeKind { Cubic, Square2d, Hex2d, Ring, Line, Fcc, Hex2dVertical };

// "cubic", "square2d", "hex2d", "ring", "line", "fcc", "hex2d_vertical".
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

// The shapes of the offset lattices. hex2d: odd rows sit half a module right, rows sqrt(3)/2
// apart, so every module touches six others (fewer at the border); hex2d_vertical likewise, its
// rows one above another (row y at height y * sqrt(3)/2, y = 0 on the ground). fcc: odd layers sit half a
// module right in x and in y, layers sqrt(2)/2 apart, so every module touches twelve.
inline constexpr double kShiftedRowOffset = 0.5;
inline constexpr double kHexRowSpacing = std::numbers::sqrt3 / 2;
inline constexpr double kFccLayerSpacing = std::numbers::sqrt2 / 2;

// Whether a kind is hexagonal in the plane: hex2d and hex2d_vertical, whose lattice coordinates
// are (column, row, 0) alike.
inline bool hexagonal(LatticeKind kind) { return kind == LatticeKind::Hex2d || kind == LatticeKind::Hex2dVertical; }

// The centre of the cell at lattice coordinates (x, y, z), one module size apart from the next;
// z is up. For every kind but the ring (whose cells are numbered around a circle).
inline std::array<float, 3> cell_centre(const LatticeSpec& spec, uint32_t x, uint32_t y, uint32_t z) {
  constexpr float shift = float(kShiftedRowOffset);
  switch (spec.kind) {
    case LatticeKind::Hex2d: return {float(x) + ((y & 1) ? shift : 0.0f), float(y) * float(kHexRowSpacing), 0};
    case LatticeKind::Hex2dVertical: return {float(x) + ((y & 1) ? shift : 0.0f), 0, float(y) * float(kHexRowSpacing)};
    case LatticeKind::Fcc: {
      const float offset = (z & 1) ? shift : 0.0f;
      return {float(x) + offset, float(y) + offset, float(z) * float(kFccLayerSpacing)};
    }
    default: return {float(x), float(y), float(z)};
  }
}
// A ring's cells: neighbours one module apart (a chord of 1) around a circle.
std::array<float, 3> ring_cell_centre(const LatticeSpec& spec, ModuleId m);
// The centre of module m's cell. Computed, not kept: 12 bytes a module (12 MB for a 100^3
// lattice) on every rank. Inline, since the contact graph asks for every module's neighbours.
// The lattice coordinates (x, y, z) of cell m.
inline std::array<uint32_t, 3> cell_coordinates(const LatticeSpec& spec, ModuleId m) {
  const uint32_t nx = spec.size[0], ny = spec.size[1], row = m / nx;
  return {m - row * nx, row % ny, row / ny};
}
// The cell at lattice coordinates (x, y, z), or none outside the lattice.
inline std::optional<ModuleId> cell_at(const LatticeSpec& spec, int64_t x, int64_t y, int64_t z) {
  const auto& n = spec.size;
  if (x < 0 || y < 0 || z < 0 || x >= n[0] || y >= n[1] || z >= n[2]) return std::nullopt;
  return static_cast<ModuleId>(x + n[0] * (y + n[1] * z));
}
inline std::array<float, 3> cell_position(const LatticeSpec& spec, ModuleId m) {
  if (spec.kind == LatticeKind::Ring) return ring_cell_centre(spec, m);
  const auto [x, y, z] = cell_coordinates(spec, m);
  return cell_centre(spec, x, y, z);
}

// The lattice coordinates (inclusive, x y z) of the cells whose centres may lie in the box
// [lo, hi]: every one that does, and at most a rounding's worth more. `empty` when there are none,
// and always for a ring, whose cells lie on a circle (its modules are few: callers list them).
struct CellRange {
  std::array<uint32_t, 3> from{}, to{};
  bool empty = true;
};
// How far past a box's side a cell is still taken in: float rounding of its centre.
inline constexpr double kCellRounding = 1e-3;
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
  // The range takes in both a shifted row's cells and an unshifted one's; each row (hex2d) or
  // layer (fcc) narrows it to its own: a column fewer, in x and y for fcc.
  const bool hex = hexagonal(spec.kind), fcc = spec.kind == LatticeKind::Fcc;
  // Narrows [from, to] to the cells of a row shifted by `shift`; false when none is left.
  const auto narrow = [](uint32_t& from, uint32_t& to, float low, float high, double shift) {
    const double a = std::max(double(from), std::ceil(double(low) - shift - kCellRounding)),
                 b = std::min(double(to), std::floor(double(high) - shift + kCellRounding));
    if (!(a <= b)) return false;
    from = static_cast<uint32_t>(a);
    to = static_cast<uint32_t>(b);
    return true;
  };
  for (uint32_t z = range.from[2]; z <= range.to[2]; ++z) {
    const double layer_shift = fcc && (z & 1) ? kShiftedRowOffset : 0.0;
    uint32_t y_from = range.from[1], y_to = range.to[1];
    if (fcc && !narrow(y_from, y_to, lo[1], hi[1], layer_shift)) continue;
    for (uint32_t y = y_from; y <= y_to; ++y) {
      uint32_t x_from = range.from[0], x_to = range.to[0];
      if ((fcc || hex) && !narrow(x_from, x_to, lo[0], hi[0], layer_shift + (hex && (y & 1) ? kShiftedRowOffset : 0.0)))
        continue;
      for (uint32_t x = x_from; x <= x_to; ++x) {
        const std::array<float, 3> p = cell_centre(spec, x, y, z);
        if (p[0] >= lo[0] && p[0] <= hi[0] && p[1] >= lo[1] && p[1] <= hi[1] && p[2] >= lo[2] && p[2] <= hi[2])
          visit(x + nx * (y + ny * z), p);
      }
    }
  }
}

// The links of a cell to its lattice neighbours with larger ids, numbered by *slot*: +x, +y, +z
// for cubic, square2d and line (those a size leaves out are outside the lattice); for hex2d and
// hex2d_vertical +x and the two cells of the row above; for fcc +x, +y and the four cells of the layer above (from
// an even layer at (x, y), x - 1 .. x and y - 1 .. y; from an odd one, x .. x + 1 and y .. y + 1).
// A ring has none (its last cell's neighbour is its first). A module's bonds to its lattice
// neighbours are kept as a bit per slot (sim/bond_set.h): a latched million take a byte each.
inline constexpr int kMaxLinkSlots = 6;
// The step from a cell in an odd row (hex2d) or layer (fcc), or not, to its link in `slot`.
inline std::array<int32_t, 3> link_step(LatticeKind kind, int slot, bool odd) {
  if (slot == 0) return {1, 0, 0};
  if (hexagonal(kind)) return {slot == 1 ? (odd ? 0 : -1) : (odd ? 1 : 0), 1, 0};
  if (kind == LatticeKind::Fcc) {
    if (slot == 1) return {0, 1, 0};
    const int32_t from = odd ? 0 : -1, k = slot - 2;
    return {from + (k & 1), from + (k >> 1), 1};
  }
  return {0, slot == 1 ? 1 : 0, slot == 2 ? 1 : 0};
}
inline int link_slots(LatticeKind kind) {
  switch (kind) {
    case LatticeKind::Ring: return 0;
    case LatticeKind::Fcc: return kMaxLinkSlots;
    default: return 3;
  }
}
// Calls visit(slot, neighbour) for each link of cell m to a larger id, in slot order (which is
// the neighbours' order).
template <typename Visit>
void for_links_above(const LatticeSpec& spec, ModuleId m, Visit&& visit) {
  if (m >= spec.module_count()) return;
  const auto [x, y, z] = cell_coordinates(spec, m);
  const bool odd = ((hexagonal(spec.kind) ? y : z) & 1) != 0;
  for (int slot = 0; slot < link_slots(spec.kind); ++slot) {
    const auto step = link_step(spec.kind, slot, odd);
    if (const auto o = cell_at(spec, int64_t{x} + step[0], int64_t{y} + step[1], int64_t{z} + step[2])) visit(slot, *o);
  }
}
// Calls visit(slot, neighbour) for each cell with a smaller id linked to m, and the slot of its
// link to m.
template <typename Visit>
void for_links_below(const LatticeSpec& spec, ModuleId m, Visit&& visit) {
  if (m >= spec.module_count()) return;
  const auto [x, y, z] = cell_coordinates(spec, m);
  const bool hex = hexagonal(spec.kind);
  for (int slot = 0; slot < link_slots(spec.kind); ++slot) {
    // The row or layer a slot climbs does not hang on parity; the source's parity fixes the rest.
    const auto climb = link_step(spec.kind, slot, false);
    const int64_t source_row = hex ? int64_t{y} - climb[1] : int64_t{z} - climb[2];
    if (source_row < 0) continue;
    const auto step = link_step(spec.kind, slot, (source_row & 1) != 0);
    if (const auto o = cell_at(spec, int64_t{x} - step[0], int64_t{y} - step[1], int64_t{z} - step[2])) visit(slot, *o);
  }
}

// Calls visit(a, b) for every two neighbouring cells a < b both occupied (`occupied` empty:
// every cell), ascending, but for a ring's (0, n - 1), which comes last.
template <typename Visit>
void for_lattice_pairs(const LatticeSpec& spec, std::span<const uint8_t> occupied, Visit&& visit) {
  const auto count = static_cast<ModuleId>(spec.module_count());
  const auto in = [&](ModuleId m) { return occupied.empty() || occupied[m] != 0; };
  for (ModuleId m = 0; m < count; ++m) {
    if (!in(m)) continue;
    if (spec.kind == LatticeKind::Ring) {
      if (m + 1 < count && in(m + 1)) visit(m, m + 1);
    } else {
      for_links_above(spec, m, [&](int, ModuleId o) {
        if (in(o)) visit(m, o);
      });
    }
  }
  if (spec.kind == LatticeKind::Ring && in(0) && in(count - 1)) visit(ModuleId{0}, count - 1);
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

// The face adjacency among the occupied cells of a lattice (`occupied` empty: every cell), made
// straight from the cells: no list of pairs (24 MB for 100^3) is held beside it.
NeighborGraph lattice_graph(const LatticeSpec& spec, std::span<const uint8_t> occupied);

// fcc (face-centred cubic, Catoms 3D): square layers one on another, each odd layer shifted by
// half a module in x and y, layers sqrt(2)/2 apart, so that every module touches 12 others: 4
// in its layer (x +-1, y +-1), 4 in the layer above and 4 below (from an even layer at (x, y) the
// cells (x-1..x, y-1..y) of the odd layers; from an odd layer the cells (x..x+1, y..y+1)).
//
// Ring needs at least 3 modules; every size at least 1. The caller checks those (the scenario
// loader reports them against the file).
// Without `with_graph`, it keeps no graph (a physical world's: its contacts make the graph).
Lattice make_lattice(const LatticeSpec& spec, bool with_graph = true);
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
