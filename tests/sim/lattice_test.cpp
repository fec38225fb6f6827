#include "sim/lattice.h"

#include <gtest/gtest.h>

#include <cmath>

namespace dw::sim {
namespace {

uint32_t degree(const Lattice& l, ModuleId m) { return static_cast<uint32_t>(l.graph->neighbors(m).size()); }

TEST(Lattice, CubeHasItsFaceAdjacentPairsOnly) {
  const Lattice l = make_lattice({LatticeKind::Cubic, {10, 10, 10}});
  ASSERT_EQ(l.positions.size(), 1000u);
  EXPECT_EQ(l.graph->edge_count(), 2 * 2700u);
  EXPECT_EQ(degree(l, 5 + 10 * (5 + 10 * 5)), 6u);
  EXPECT_EQ(degree(l, 0), 3u);
  // Neighbours are exactly one module size apart.
  for (ModuleId m = 0; m < 1000; ++m)
    for (ModuleId n : l.graph->neighbors(m)) {
      const auto& a = l.positions[m];
      const auto& b = l.positions[n];
      EXPECT_FLOAT_EQ(std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]), 1.0f);
    }
}

TEST(Lattice, HexInteriorModulesHaveSixNeighboursOneApart) {
  const Lattice l = make_lattice({LatticeKind::Hex2d, {8, 6, 1}});
  for (uint32_t y = 1; y + 1 < 6; ++y)
    for (uint32_t x = 1; x + 1 < 8; ++x) EXPECT_EQ(degree(l, x + 8 * y), 6u) << x << "," << y;
  for (ModuleId m = 0; m < 48; ++m)
    for (ModuleId n : l.graph->neighbors(m)) {
      const auto& a = l.positions[m];
      const auto& b = l.positions[n];
      EXPECT_NEAR(std::hypot(a[0] - b[0], a[1] - b[1]), 1.0, 1e-5);
      EXPECT_TRUE(l.graph->adjacent(n, m));
    }
  // And nothing else is within one module size.
  uint32_t close = 0;
  for (ModuleId m = 0; m < 48; ++m)
    for (ModuleId n = m + 1; n < 48; ++n)
      close += std::hypot(l.positions[m][0] - l.positions[n][0], l.positions[m][1] - l.positions[n][1]) < 1.01;
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
  for (LatticeKind k :
       {LatticeKind::Cubic, LatticeKind::Square2d, LatticeKind::Hex2d, LatticeKind::Ring, LatticeKind::Line})
    EXPECT_EQ(lattice_from_name(lattice_name(k)), k);
  EXPECT_FALSE(lattice_from_name("hexagonal"));
}

TEST(NeighborGraph, FromPairsSortsAndDeduplicates) {
  const std::vector<std::pair<ModuleId, ModuleId>> pairs{{2, 0}, {0, 1}, {0, 2}, {3, 1}};
  const NeighborGraph g = NeighborGraph::from_pairs(4, pairs);
  EXPECT_EQ(std::vector<ModuleId>(g.neighbors(0).begin(), g.neighbors(0).end()), (std::vector<ModuleId>{1, 2}));
  EXPECT_EQ(std::vector<ModuleId>(g.neighbors(1).begin(), g.neighbors(1).end()), (std::vector<ModuleId>{0, 3}));
  EXPECT_EQ(g.edge_count(), 6u);
}

}  // namespace
}  // namespace dw::sim
