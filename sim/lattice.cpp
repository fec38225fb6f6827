#include "sim/lattice.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace dw::sim {
namespace {

constexpr std::pair<LatticeKind, std::string_view> kNames[] = {
    {LatticeKind::Cubic, "cubic"}, {LatticeKind::Square2d, "square2d"}, {LatticeKind::Hex2d, "hex2d"},
    {LatticeKind::Ring, "ring"},   {LatticeKind::Line, "line"},         {LatticeKind::Fcc, "fcc"},
};

// The graph's edges between occupied cells.
std::shared_ptr<const NeighborGraph> between_occupied(const NeighborGraph& graph, std::span<const uint8_t> occupied) {
  std::vector<std::pair<ModuleId, ModuleId>> pairs;
  for (ModuleId m = 0; m < graph.module_count(); ++m)
    for (ModuleId o : graph.neighbors(m))
      if (m < o && occupied[m] && occupied[o]) pairs.emplace_back(m, o);
  return std::make_shared<const NeighborGraph>(NeighborGraph::from_pairs(graph.module_count(), pairs));
}

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
    case LatticeKind::Hex2d: return 2;
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
  if (spec.kind == LatticeKind::Hex2d) {
    spacing[1] = kHexRowSpacing;
    shift[0] = kShiftedRowOffset;
  } else if (spec.kind == LatticeKind::Fcc) {
    spacing[2] = kFccLayerSpacing;
    shift[0] = shift[1] = kShiftedRowOffset;
  }
  CellRange range;
  for (int i = 0; i < 3; ++i) {
    const double from = std::ceil((double(lo[i]) - shift[i]) / spacing[i] - kCellRounding),
                 to = std::floor(double(hi[i]) / spacing[i] + kCellRounding);
    const double last = double(spec.size[size_t(i)]) - 1;
    // Not finite, or outside the lattice: no cell (a NaN fails every comparison).
    if (!(from <= to) || !(to >= 0) || !(from <= last)) return {};
    range.from[size_t(i)] = static_cast<uint32_t>(std::max(from, 0.0));
    range.to[size_t(i)] = static_cast<uint32_t>(std::min(to, last));
  }
  range.empty = false;
  return range;
}

Lattice make_lattice(const LatticeSpec& spec) {
  Lattice l;
  l.spec = spec;
  const uint32_t nx = spec.size[0], ny = spec.size[1], nz = spec.size[2];
  const uint32_t count = static_cast<uint32_t>(spec.module_count());
  std::vector<std::pair<ModuleId, ModuleId>> pairs;
  auto id = [&](uint32_t x, uint32_t y, uint32_t z) { return x + nx * (y + ny * z); };

  switch (spec.kind) {
    case LatticeKind::Cubic:
    case LatticeKind::Square2d:
      for (uint32_t z = 0; z < nz; ++z)
        for (uint32_t y = 0; y < ny; ++y)
          for (uint32_t x = 0; x < nx; ++x) {
            if (x + 1 < nx) pairs.emplace_back(id(x, y, z), id(x + 1, y, z));
            if (y + 1 < ny) pairs.emplace_back(id(x, y, z), id(x, y + 1, z));
            if (z + 1 < nz) pairs.emplace_back(id(x, y, z), id(x, y, z + 1));
          }
      break;
    case LatticeKind::Hex2d: {
      for (uint32_t y = 0; y < ny; ++y)
        for (uint32_t x = 0; x < nx; ++x) {
          if (x + 1 < nx) pairs.emplace_back(id(x, y, 0), id(x + 1, y, 0));
          if (y + 1 < ny) {
            // The row above: the same x, and x - 1 (even rows) or x + 1 (odd rows).
            pairs.emplace_back(id(x, y, 0), id(x, y + 1, 0));
            const int64_t other = (y & 1) ? int64_t{x} + 1 : int64_t{x} - 1;
            if (other >= 0 && other < nx) pairs.emplace_back(id(x, y, 0), id(uint32_t(other), y + 1, 0));
          }
        }
      break;
    }
    case LatticeKind::Fcc: {
      for (uint32_t z = 0; z < nz; ++z)
        for (uint32_t y = 0; y < ny; ++y)
          for (uint32_t x = 0; x < nx; ++x) {
            if (x + 1 < nx) pairs.emplace_back(id(x, y, z), id(x + 1, y, z));
            if (y + 1 < ny) pairs.emplace_back(id(x, y, z), id(x, y + 1, z));
            if (z + 1 == nz) continue;
            // The four cells of the layer above: x - 1 .. x from an even layer, x .. x + 1 from an odd one.
            const int64_t from = (z & 1) ? 0 : -1;
            for (int64_t dy = from; dy <= from + 1; ++dy)
              for (int64_t dx = from; dx <= from + 1; ++dx) {
                const int64_t ax = int64_t{x} + dx, ay = int64_t{y} + dy;
                if (ax >= 0 && ax < nx && ay >= 0 && ay < ny)
                  pairs.emplace_back(id(x, y, z), id(uint32_t(ax), uint32_t(ay), z + 1));
              }
          }
      break;
    }
    case LatticeKind::Ring: {
      for (uint32_t i = 0; i < nx; ++i) pairs.emplace_back(i, (i + 1) % nx);
      break;
    }
    case LatticeKind::Line:
      for (uint32_t i = 0; i + 1 < nx; ++i) pairs.emplace_back(i, i + 1);
      break;
  }
  l.occupied.assign(count, 1);
  l.graph = std::make_shared<const NeighborGraph>(NeighborGraph::from_pairs(count, pairs));
  return l;
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
  lattice.graph = between_occupied(*lattice.graph, lattice.occupied);
}

std::shared_ptr<const NeighborGraph> lattice_graph(const Lattice& lattice) {
  if (lattice.graph) return lattice.graph;
  return between_occupied(*make_lattice(lattice.spec).graph, lattice.occupied);
}

}  // namespace dw::sim
