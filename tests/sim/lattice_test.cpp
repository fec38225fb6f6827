#include "sim/lattice.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <vector>

namespace dw::sim {
namespace {

uint32_t degree(const Lattice& l, ModuleId m) { return static_cast<uint32_t>(l.graph->neighbors(m).size()); }

TEST(Lattice, CubeHasItsFaceAdjacentPairsOnly) {
  const Lattice l = make_lattice({LatticeKind::Cubic, {10, 10, 10}});
  ASSERT_EQ(l.spec.module_count(), 1000u);
  EXPECT_EQ(l.graph->edge_count(), 2 * 2700u);
  EXPECT_EQ(degree(l, 5 + 10 * (5 + 10 * 5)), 6u);
  EXPECT_EQ(degree(l, 0), 3u);
  // Neighbours are exactly one module size apart.
  for (ModuleId m = 0; m < 1000; ++m)
    for (ModuleId n : l.graph->neighbors(m)) {
      const auto& a = l.position(m);
      const auto& b = l.position(n);
      EXPECT_FLOAT_EQ(std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]), 1.0f);
    }
}

// Catoms 3D: every pair one module apart is a neighbour pair and no other pair is, checked over all
// pairs; modules with every one of their cells inside the block have 12.
TEST(Lattice, FccNeighboursAreExactlyThePairsOneModuleApart) {
  constexpr uint32_t n = 5;
  const Lattice l = make_lattice({LatticeKind::Fcc, {n, n, n}});
  ASSERT_EQ(l.spec.module_count(), n * n * n);
  uint32_t twelve = 0;
  for (ModuleId a = 0; a < l.spec.module_count(); ++a) {
    const auto nbrs = l.graph->neighbors(a);
    twelve += nbrs.size() == 12;
    EXPECT_LE(nbrs.size(), 12u);
    for (ModuleId b = 0; b < l.spec.module_count(); ++b) {
      if (a == b) continue;
      const auto &p = l.position(a), &q = l.position(b);
      const float d = std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
      const bool listed = std::find(nbrs.begin(), nbrs.end(), b) != nbrs.end();
      EXPECT_EQ(listed, std::abs(d - 1) < 1e-5f) << a << " and " << b << " are " << d << " apart";
      EXPECT_GT(d, 0.999f) << "two modules overlap";
    }
  }
  // Interior: x and y from 1 to n - 2 in every layer but the first and the last.
  EXPECT_EQ(twelve, (n - 2) * (n - 2) * (n - 2));
  // The layers: an odd one shifted half a module in x and y, sqrt(2)/2 above the even one.
  EXPECT_FLOAT_EQ(l.position(n * n)[0], 0.5f);
  EXPECT_FLOAT_EQ(l.position(n * n)[2], std::sqrt(2.0f) / 2);
}

TEST(Lattice, HexInteriorModulesHaveSixNeighboursOneApart) {
  const Lattice l = make_lattice({LatticeKind::Hex2d, {8, 6, 1}});
  for (uint32_t y = 1; y + 1 < 6; ++y)
    for (uint32_t x = 1; x + 1 < 8; ++x) EXPECT_EQ(degree(l, x + 8 * y), 6u) << x << "," << y;
  for (ModuleId m = 0; m < 48; ++m)
    for (ModuleId n : l.graph->neighbors(m)) {
      const auto& a = l.position(m);
      const auto& b = l.position(n);
      EXPECT_NEAR(std::hypot(a[0] - b[0], a[1] - b[1]), 1.0, 1e-5);
      EXPECT_TRUE(l.graph->adjacent(n, m));
    }
  // And nothing else is within one module size.
  uint32_t close = 0;
  for (ModuleId m = 0; m < 48; ++m)
    for (ModuleId n = m + 1; n < 48; ++n)
      close += std::hypot(l.position(m)[0] - l.position(n)[0], l.position(m)[1] - l.position(n)[1]) < 1.01;
  EXPECT_EQ(2 * close, l.graph->edge_count());
}

TEST(Lattice, RingLineAndSquare) {
  const Lattice ring = make_lattice({LatticeKind::Ring, {7, 1, 1}});
  for (ModuleId m = 0; m < 7; ++m) EXPECT_EQ(degree(ring, m), 2u);
  EXPECT_TRUE(ring.graph->adjacent(0, 6));
  const Lattice line = make_lattice({LatticeKind::Line, {5, 1, 1}});
  EXPECT_EQ(degree(line, 0), 1u);
  EXPECT_EQ(degree(line, 2), 2u);
  EXPECT_FALSE(line.graph->adjacent(0, 4));
  const Lattice square = make_lattice({LatticeKind::Square2d, {4, 3, 1}});
  EXPECT_EQ(degree(square, 1 + 4 * 1), 4u);
  EXPECT_EQ(square.graph->edge_count(), 2u * (3 * 3 + 4 * 2));
}

TEST(Lattice, NamesRoundTrip) {
  for (LatticeKind k : {LatticeKind::Cubic, LatticeKind::Square2d, LatticeKind::Hex2d, LatticeKind::Ring,
                        LatticeKind::Line, LatticeKind::Fcc, LatticeKind::Hex2dVertical})
    EXPECT_EQ(lattice_from_name(lattice_name(k)), k);
  EXPECT_EQ(lattice_name(LatticeKind::Hex2dVertical), "hex2d_vertical");
  EXPECT_EQ(lattice_dimensions(LatticeKind::Hex2dVertical), 2);
  EXPECT_FALSE(lattice_from_name("hexagonal"));
}

// 2-D catoms in a vertical plane: hex2d stood up, its rows climbing z from the ground row (z = 0)
// sqrt(3)/2 apart, odd rows half a module right, every cell at y = 0; the same ids and the same
// graph as hex2d's.
TEST(Lattice, Hex2dVerticalIsHex2dStoodUpInTheXzPlane) {
  const Lattice flat = make_lattice({LatticeKind::Hex2d, {6, 5, 1}});
  const Lattice up = make_lattice({LatticeKind::Hex2dVertical, {6, 5, 1}});
  for (ModuleId m = 0; m < 30; ++m) {
    const auto a = flat.position(m), b = up.position(m);
    EXPECT_EQ(b, (std::array<float, 3>{a[0], 0, a[1]})) << m;
  }
  EXPECT_EQ(up.position(6 + 1), (std::array<float, 3>{1.5f, 0, float(kHexRowSpacing)}));  // row 1, column 1
  EXPECT_EQ(up.graph->ids, flat.graph->ids);
  EXPECT_EQ(up.graph->begin, flat.graph->begin);
  EXPECT_EQ(degree(up, 6 * 2 + 2), 6u);
}

// Boxes left empty, overlapping, reaching past the lattice's edge, one cell or many: the cells any
// box holds are empty and no others, and no pair touches an empty cell.
TEST(Lattice, BoxesLeftEmptyAreExactlyTheCellsAnyBoxHolds) {
  const std::vector<LatticeBox> boxes = {{{{0, 0, 0}, {1, 1, 1}}},
                                         {{{1, 1, 1}, {2, 3, 1}}},
                                         {{{4, 0, 2}, {9, 9, 9}}},
                                         {{{2, 2, 0}, {2, 2, 0}}},
                                         {{{0, 4, 0}, {0, 4, 3}}}};
  Lattice l = make_lattice({LatticeKind::Cubic, {5, 5, 4}});
  leave_empty(l, boxes);
  const auto inside = [](const LatticeBox& b, uint32_t x, uint32_t y, uint32_t z) {
    return x >= b[0][0] && x <= b[1][0] && y >= b[0][1] && y <= b[1][1] && z >= b[0][2] && z <= b[1][2];
  };
  size_t empty = 0;
  for (uint32_t z = 0; z < 4; ++z)
    for (uint32_t y = 0; y < 5; ++y)
      for (uint32_t x = 0; x < 5; ++x) {
        const bool in_a_box = std::ranges::any_of(boxes, [&](const LatticeBox& b) { return inside(b, x, y, z); });
        const ModuleId m = x + 5 * (y + 5 * z);
        EXPECT_EQ(l.occupied[m] == 0, in_a_box) << x << " " << y << " " << z;
        empty += in_a_box;
        for (ModuleId o : l.graph->neighbors(m)) EXPECT_TRUE(l.occupied[m] && l.occupied[o]) << m << " " << o;
      }
  EXPECT_EQ(empty, 8u + (6u - 1u) + 10u + 1u + 4u);  // the boxes, the second less the cell it shares
}

// The links above a cell and those below it are the same pairs, seen from each end, with the
// same slot; above, they come in the order of their ids; and they are the lattice graph's pairs.
TEST(LatticeLinks, BelowIsAboveSeenFromTheOtherEndAndBothAreTheGraphsPairs) {
  const LatticeSpec specs[] = {
      {LatticeKind::Cubic, {4, 3, 5}},    {LatticeKind::Cubic, {1, 1, 1}}, {LatticeKind::Cubic, {2, 1, 3}},
      {LatticeKind::Square2d, {5, 4, 1}}, {LatticeKind::Line, {7, 1, 1}},  {LatticeKind::Hex2d, {5, 6, 1}},
      {LatticeKind::Hex2d, {2, 7, 1}},    {LatticeKind::Fcc, {4, 5, 6}},   {LatticeKind::Fcc, {1, 3, 2}},
      {LatticeKind::Fcc, {3, 2, 3}},      {LatticeKind::Fcc, {2, 2, 2}},
  };
  for (const LatticeSpec& spec : specs) {
    SCOPED_TRACE(std::string(lattice_name(spec.kind)) + " " + std::to_string(spec.module_count()));
    struct Link {
      ModuleId low, high;
      int slot;
      auto operator<=>(const Link&) const = default;
    };
    std::vector<Link> above, below;
    const auto n = static_cast<ModuleId>(spec.module_count());
    for (ModuleId m = 0; m < n; ++m) {
      ModuleId last = m;
      for_links_above(spec, m, [&](int slot, ModuleId o) {
        EXPECT_GT(o, last) << "module " << m << " slot " << slot;
        last = o;
        above.push_back({m, o, slot});
      });
      for_links_below(spec, m, [&](int slot, ModuleId o) {
        EXPECT_LT(o, m);
        below.push_back({o, m, slot});
      });
    }
    std::sort(below.begin(), below.end());
    EXPECT_EQ(above, below);
    const Lattice l = make_lattice(spec);
    EXPECT_EQ(2 * above.size(), l.graph->edge_count());
    for (const Link& x : above) EXPECT_TRUE(l.graph->adjacent(x.low, x.high));
  }
}

// A graph made straight from the cells between those occupied equals the one kept by the lattice
// whose boxes were left empty, and one made from the pairs.
TEST(LatticeGraph, MadeFromTheCellsEqualsTheOneFromThePairs) {
  for (const LatticeSpec& spec : {LatticeSpec{LatticeKind::Fcc, {4, 5, 6}}, LatticeSpec{LatticeKind::Ring, {9, 1, 1}},
                                  LatticeSpec{LatticeKind::Hex2d, {6, 5, 1}}}) {
    std::mt19937 random(5);
    std::vector<uint8_t> occupied(spec.module_count());
    for (uint8_t& o : occupied) o = random() % 4 != 0;
    std::vector<std::pair<ModuleId, ModuleId>> pairs;
    for_lattice_pairs(spec, occupied, [&](ModuleId a, ModuleId b) {
      EXPECT_TRUE(occupied[a] && occupied[b]);
      pairs.emplace_back(b, a);  // turned round: from_pairs sorts them
    });
    const NeighborGraph made = lattice_graph(spec, occupied);
    const NeighborGraph from = NeighborGraph::from_pairs(static_cast<uint32_t>(occupied.size()), pairs);
    EXPECT_EQ(made.begin, from.begin);
    EXPECT_EQ(made.ids, from.ids);
  }
}

TEST(NeighborGraph, FromPairsSortsAndDeduplicates) {
  const std::vector<std::pair<ModuleId, ModuleId>> pairs{{2, 0}, {0, 1}, {0, 2}, {3, 1}};
  const NeighborGraph g = NeighborGraph::from_pairs(4, pairs);
  EXPECT_EQ(std::vector<ModuleId>(g.neighbors(0).begin(), g.neighbors(0).end()), (std::vector<ModuleId>{1, 2}));
  EXPECT_EQ(std::vector<ModuleId>(g.neighbors(1).begin(), g.neighbors(1).end()), (std::vector<ModuleId>{0, 3}));
  EXPECT_EQ(g.edge_count(), 6u);
}

// Sorted pairs, each a < b, skip the sorting: the graph is the one unsorted pairs give.
TEST(NeighborGraph, SortedPairsGiveTheSameGraphAsShuffledOnes) {
  std::vector<std::pair<ModuleId, ModuleId>> sorted;
  for (ModuleId a = 0; a < 40; ++a)
    for (ModuleId b = a + 1; b < 40; ++b)
      if ((a * 7 + b * 3) % 5 == 0) sorted.emplace_back(a, b);
  std::vector<std::pair<ModuleId, ModuleId>> shuffled;
  for (size_t i = sorted.size(); i-- > 0;) {  // backwards, every other pair turned round
    const auto& [a, b] = sorted[i];
    shuffled.emplace_back(i % 2 ? a : b, i % 2 ? b : a);
  }
  shuffled.push_back(shuffled.front());
  const NeighborGraph fast = NeighborGraph::from_pairs(40, sorted), slow = NeighborGraph::from_pairs(40, shuffled);
  EXPECT_EQ(fast.begin, slow.begin);
  EXPECT_EQ(fast.ids, slow.ids);
  for (ModuleId m = 0; m < 40; ++m) EXPECT_TRUE(std::ranges::is_sorted(fast.neighbors(m)));
}

// A graph changed by pairs gone and made equals the graph built from the pairs after the change,
// at the ends of the id range and in the middle, the lists of untouched modules moved along.
TEST(NeighborGraph, ChangedByPairsGoneAndMadeEqualsTheGraphBuiltAfresh) {
  std::vector<std::pair<ModuleId, ModuleId>> pairs, gone, made, after;
  for (ModuleId a = 0; a < 30; ++a)
    for (ModuleId b = a + 1; b < 30; ++b) {
      const bool in = (a * 5 + b * 11) % 7 < 2;
      const bool flip = (a == 0 || b == 29 || (a * 3 + b) % 13 == 0);
      if (in && flip) gone.emplace_back(a, b);
      if (!in && flip) made.emplace_back(a, b);
      if (in) pairs.emplace_back(a, b);
      if (in != flip) after.emplace_back(a, b);
    }
  ASSERT_FALSE(gone.empty());
  ASSERT_FALSE(made.empty());
  const NeighborGraph g = NeighborGraph::from_pairs(30, pairs).changed(gone, made);
  const NeighborGraph fresh = NeighborGraph::from_pairs(30, after);
  EXPECT_EQ(g.begin, fresh.begin);
  EXPECT_EQ(g.ids, fresh.ids);
  // Nothing changed: the same graph.
  const NeighborGraph same = fresh.changed({}, {});
  EXPECT_EQ(same.begin, fresh.begin);
  EXPECT_EQ(same.ids, fresh.ids);

  // A window (docs/design.md §12a) holding modules 0-11 and then 6-19: the lists it keeps take the
  // changes, those it gains are given whole, those it loses come out empty; the result is the
  // fresh graph's window.
  auto before = std::make_shared<std::vector<uint8_t>>(30, 0), now = std::make_shared<std::vector<uint8_t>>(30, 0);
  std::fill(before->begin(), before->begin() + 12, 1);
  std::fill(now->begin() + 6, now->begin() + 20, 1);
  const NeighborGraph held = NeighborGraph::from_pairs(30, pairs).held_only(before);
  EXPECT_TRUE(held.holds(3));
  EXPECT_FALSE(held.holds(12));
  EXPECT_TRUE(held.neighbors(12).empty());
  std::vector<std::pair<ModuleId, ModuleId>> gained;
  for (const auto& [a, b] : after) {
    if ((*now)[a] && !(*before)[a]) gained.emplace_back(a, b);
    if ((*now)[b] && !(*before)[b]) gained.emplace_back(b, a);
  }
  std::sort(gained.begin(), gained.end());
  ASSERT_FALSE(gained.empty());
  const NeighborGraph moved = held.changed(gone, made, now, gained);
  const NeighborGraph window = NeighborGraph::from_pairs(30, after).held_only(now);
  EXPECT_EQ(moved.held, now);
  EXPECT_EQ(moved.begin, window.begin);
  EXPECT_EQ(moved.ids, window.ids);
  EXPECT_FALSE(moved.ids.empty());
}

// The cells make_lattice's graph joins are one module apart, for every kind: the positions and
// the adjacency come from one formula each.
TEST(CellPosition, NeighboursInTheLatticeGraphAreOneModuleApart) {
  for (const LatticeSpec spec :
       {LatticeSpec{LatticeKind::Cubic, {4, 3, 5}}, LatticeSpec{LatticeKind::Square2d, {6, 4, 1}},
        LatticeSpec{LatticeKind::Hex2d, {5, 6, 1}}, LatticeSpec{LatticeKind::Fcc, {4, 4, 4}},
        LatticeSpec{LatticeKind::Ring, {12, 1, 1}}, LatticeSpec{LatticeKind::Line, {9, 1, 1}},
        LatticeSpec{LatticeKind::Hex2dVertical, {5, 6, 1}}}) {
    const Lattice lattice = make_lattice(spec);
    for (ModuleId m = 0; m < spec.module_count(); ++m)
      for (ModuleId o : lattice.graph->neighbors(m)) {
        const auto a = lattice.position(m), b = cell_position(spec, o);
        EXPECT_NEAR(std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]), 1.0f, 1e-5f)
            << lattice_name(spec.kind) << " " << m << "-" << o;
      }
  }
}

// The cells found in a box are exactly those whose centres lie in it, ascending, on every kind
// of lattice but the ring (none), for boxes inside, across and outside the lattice's edges.
TEST(CellsInBox, VisitsTheModulesWhoseCellsLieInTheBox) {
  std::mt19937 random(5);
  std::uniform_real_distribution<float> corner(-3, 9), width(0, 4);
  for (const LatticeSpec spec :
       {LatticeSpec{LatticeKind::Cubic, {4, 3, 5}}, LatticeSpec{LatticeKind::Square2d, {6, 4, 1}},
        LatticeSpec{LatticeKind::Hex2d, {5, 6, 1}}, LatticeSpec{LatticeKind::Fcc, {4, 4, 6}},
        LatticeSpec{LatticeKind::Ring, {12, 1, 1}}, LatticeSpec{LatticeKind::Line, {9, 1, 1}},
        LatticeSpec{LatticeKind::Hex2dVertical, {5, 6, 1}}}) {
    size_t found = 0;
    for (int box = 0; box < 300; ++box) {
      std::array<float, 3> lo{}, hi{};
      for (size_t i = 0; i < 3; ++i) hi[i] = (lo[i] = corner(random)) + width(random);
      if (box % 3 == 0) lo[2] = hi[2] = 0;  // a flat box, where planar lattices lie
      if (box % 3 == 1 && spec.kind == LatticeKind::Hex2dVertical) lo[1] = hi[1] = 0;  // where it stands
      if (box % 5 == 0) {                                                              // a centre on the box's side
        lo = cell_position(spec, ModuleId(box) % uint32_t(spec.module_count()));
        for (size_t i = 0; i < 3; ++i) hi[i] = lo[i] + width(random);
      }
      std::vector<ModuleId> seen, expected;
      for_cells_in_box(spec, lo, hi, [&](ModuleId m, const std::array<float, 3>& centre) {
        seen.push_back(m);
        EXPECT_EQ(centre, cell_position(spec, m));
      });
      if (spec.kind != LatticeKind::Ring)
        for (ModuleId m = 0; m < spec.module_count(); ++m) {
          const auto p = cell_position(spec, m);
          if (p[0] >= lo[0] && p[0] <= hi[0] && p[1] >= lo[1] && p[1] <= hi[1] && p[2] >= lo[2] && p[2] <= hi[2])
            expected.push_back(m);
        }
      EXPECT_EQ(seen, expected) << lattice_name(spec.kind) << " box " << box;
      found += seen.size();
    }
    if (spec.kind != LatticeKind::Ring) {
      EXPECT_GT(found, 100u) << lattice_name(spec.kind);
    }
  }
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const LatticeSpec cube{LatticeKind::Cubic, {3, 3, 3}};
  EXPECT_FALSE(cells_in_box(cube, {-inf, -inf, -inf}, {inf, inf, inf}).empty);
  EXPECT_EQ(cells_in_box(cube, {-inf, -inf, -inf}, {inf, inf, inf}).to, (std::array<uint32_t, 3>{2, 2, 2}));
  EXPECT_TRUE(cells_in_box(cube, {nan, 0, 0}, {1, 1, 1}).empty);
  EXPECT_TRUE(cells_in_box(cube, {3.5f, 0, 0}, {9, 1, 1}).empty);
}

}  // namespace
}  // namespace dw::sim
