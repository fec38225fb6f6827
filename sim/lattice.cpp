#include "sim/lattice.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace dw::sim {
namespace {

constexpr std::pair<LatticeKind, std::string_view> kNames[] = {
    {LatticeKind::Cubic, "cubic"},
    {LatticeKind::Square2d, "square2d"},
    {LatticeKind::Hex2d, "hex2d"},
    {LatticeKind::Ring, "ring"},
    {LatticeKind::Line, "line"},
    {LatticeKind::Fcc, "fcc"},
    {LatticeKind::Hex2dVertical, "hex2d_vertical"},
};

}  // namespace

std::string_view lattice_name(LatticeKind kind) {
  for (const auto& [k, name] : kNames)
    if (k == kind) return name;
  return "?";
}

std::optional<LatticeKind> lattice_from_name(std::string_view name) {
  for (const auto& [k, n] : kNames)
    if (n == name) return k;
  return std::nullopt;
}

int lattice_dimensions(LatticeKind kind) {
  switch (kind) {
    case LatticeKind::Cubic:
    case LatticeKind::Fcc: return 3;
    case LatticeKind::Square2d:
    case LatticeKind::Hex2d:
    case LatticeKind::Hex2dVertical: return 2;
    case LatticeKind::Ring:
    case LatticeKind::Line: return 1;
  }
  return 1;
}

std::array<float, 3> ring_cell_centre(const LatticeSpec& spec, ModuleId m) {
  const uint32_t n = spec.size[0];
  const double radius = 0.5 / std::sin(std::numbers::pi / n);
  const double a = 2 * std::numbers::pi * m / n;
  return {float(radius * std::cos(a)), float(radius * std::sin(a)), 0};
}

CellRange cells_in_box(const LatticeSpec& spec, const std::array<float, 3>& lo, const std::array<float, 3>& hi) {
  if (spec.kind == LatticeKind::Ring) return {};
  // Per axis: the distance between cells, and how far right a shifted row or layer sits (hex2d's
  // odd rows in x, fcc's odd layers in x and y).
  std::array<double, 3> spacing{1, 1, 1}, shift{0, 0, 0};
  // Per lattice axis, the axis of space its cells run along (hex2d_vertical's rows climb z).
  std::array<size_t, 3> along{0, 1, 2};
  if (hexagonal(spec.kind)) {
    spacing[1] = kHexRowSpacing;
    shift[0] = kShiftedRowOffset;
    if (spec.kind == LatticeKind::Hex2dVertical) along = {0, 2, 1};
  } else if (spec.kind == LatticeKind::Fcc) {
    spacing[2] = kFccLayerSpacing;
    shift[0] = shift[1] = kShiftedRowOffset;
  }
  CellRange range;
  for (int i = 0; i < 3; ++i) {
    const size_t a = along[size_t(i)];
    const double from = std::ceil((double(lo[a]) - shift[i]) / spacing[i] - kCellRounding),
                 to = std::floor(double(hi[a]) / spacing[i] + kCellRounding);
    const double last = double(spec.size[size_t(i)]) - 1;
    // Not finite, or outside the lattice: no cell (a NaN fails every comparison).
    if (!(from <= to) || !(to >= 0) || !(from <= last)) return {};
    range.from[size_t(i)] = static_cast<uint32_t>(std::max(from, 0.0));
    range.to[size_t(i)] = static_cast<uint32_t>(std::min(to, last));
  }
  range.empty = false;
  return range;
}

Lattice make_lattice(const LatticeSpec& spec, bool with_graph) {
  Lattice l;
  l.spec = spec;
  l.occupied.assign(static_cast<size_t>(spec.module_count()), 1);
  l.graph = with_graph ? std::make_shared<const NeighborGraph>(lattice_graph(spec, {})) : nullptr;
  return l;
}

NeighborGraph lattice_graph(const LatticeSpec& spec, std::span<const uint8_t> occupied) {
  const auto count = static_cast<uint32_t>(spec.module_count());
  NeighborGraph g;
  // Each list's length, then where it begins; filling a list moves its begin to its end, and
  // the begins are put back by one.
  g.begin.assign(size_t{count} + 1, 0);
  for_lattice_pairs(spec, occupied, [&](ModuleId a, ModuleId b) { ++g.begin[a + 1], ++g.begin[b + 1]; });
  for (uint32_t m = 0; m < count; ++m) g.begin[m + 1] += g.begin[m];
  g.ids.resize(g.begin[count]);
  for_lattice_pairs(spec, occupied, [&](ModuleId a, ModuleId b) { g.ids[g.begin[a]++] = b, g.ids[g.begin[b]++] = a; });
  for (uint32_t m = count; m > 0; --m) g.begin[m] = g.begin[m - 1];
  g.begin[0] = 0;
  // Pairs come ascending, so each list has its smaller ids, then its larger, in order; but for a
  // ring's last pair.
  if (spec.kind == LatticeKind::Ring)
    for (uint32_t m = 0; m < count; ++m) std::sort(g.ids.begin() + g.begin[m], g.ids.begin() + g.begin[m + 1]);
  return g;
}

void leave_empty(Lattice& lattice, std::span<const LatticeBox> boxes) {
  const auto& n = lattice.spec.size;
  // Each box adds one to its cells through its eight corners in a difference array; sums along x,
  // then y, then z count for every cell the boxes that hold it.
  const size_t sx = size_t{n[0]} + 1, sy = size_t{n[1]} + 1, sz = size_t{n[2]} + 1;
  std::vector<int32_t> d(sx * sy * sz, 0);
  const auto at = [&](size_t x, size_t y, size_t z) -> int32_t& { return d[x + sx * (y + sy * z)]; };
  for (const auto& [from, to] : boxes) {
    if (from[0] >= n[0] || from[1] >= n[1] || from[2] >= n[2]) continue;
    const size_t x0 = from[0], y0 = from[1], z0 = from[2];
    const size_t x1 = size_t{std::min(to[0], n[0] - 1)} + 1, y1 = size_t{std::min(to[1], n[1] - 1)} + 1,
                 z1 = size_t{std::min(to[2], n[2] - 1)} + 1;
    ++at(x0, y0, z0), --at(x1, y0, z0), --at(x0, y1, z0), --at(x0, y0, z1);
    ++at(x1, y1, z0), ++at(x1, y0, z1), ++at(x0, y1, z1), --at(x1, y1, z1);
  }
  for (size_t z = 0; z < sz; ++z)
    for (size_t y = 0; y < sy; ++y)
      for (size_t x = 1; x < sx; ++x) at(x, y, z) += at(x - 1, y, z);
  for (size_t z = 0; z < sz; ++z)
    for (size_t y = 1; y < sy; ++y)
      for (size_t x = 0; x < sx; ++x) at(x, y, z) += at(x, y - 1, z);
  for (size_t z = 1; z < sz; ++z)
    for (size_t y = 0; y < sy; ++y)
      for (size_t x = 0; x < sx; ++x) at(x, y, z) += at(x, y, z - 1);
  for (uint32_t z = 0; z < n[2]; ++z)
    for (uint32_t y = 0; y < n[1]; ++y)
      for (uint32_t x = 0; x < n[0]; ++x)
        if (at(x, y, z) > 0) lattice.occupied[x + n[0] * (y + n[1] * z)] = 0;
  if (lattice.graph)
    lattice.graph = std::make_shared<const NeighborGraph>(lattice_graph(lattice.spec, lattice.occupied));
}

}  // namespace dw::sim
