#include "physics/cell_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

namespace dw::physics {
namespace {

std::vector<sim::ModuleId> visited(const CellGrid& grid, const sim::Vec3& at) {
  std::vector<sim::ModuleId> out;
  grid.around(at, [&](sim::ModuleId m, const sim::Vec3&) { out.push_back(m); });
  std::sort(out.begin(), out.end());
  return out;
}

float distance(const sim::Vec3& a, const sim::Vec3& b) { return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]); }

// Every module within the side of a point is visited, wherever the points fall in their cells,
// after insertions, moves and erasures.
TEST(CellGrid, VisitsEveryModuleWithinTheSide) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> coordinate(-6, 6);
  const auto point = [&] { return sim::Vec3{coordinate(random), coordinate(random), coordinate(random)}; };
  CellGrid grid(1.75f);
  std::vector<sim::Vec3> at(400);
  std::vector<uint8_t> in(at.size(), 1);
  grid.resize(at.size());
  for (sim::ModuleId m = 0; m < at.size(); ++m) grid.place(m, true, at[m] = point());
  for (int round = 0; round < 3; ++round) {
    for (sim::ModuleId m = 0; m < at.size(); m += 3) {
      if (!in[m]) continue;
      grid.place(m, true, at[m] = point());
    }
    for (sim::ModuleId m = static_cast<sim::ModuleId>(round); m < at.size(); m += 7)
      if (in[m]) {
        grid.place(m, false, at[m]);
        in[m] = 0;
      }
    for (int probe = 0; probe < 200; ++probe) {
      const sim::Vec3 p = point();
      const std::vector<sim::ModuleId> seen = visited(grid, p);
      for (sim::ModuleId m = 0; m < at.size(); ++m) {
        const bool listed = std::binary_search(seen.begin(), seen.end(), m);
        if (!in[m]) {
          EXPECT_FALSE(listed) << "erased module " << m;
        } else if (distance(at[m], p) <= grid.side()) {
          EXPECT_TRUE(listed) << "module " << m << " round " << round;
        }
      }
    }
  }
}

// Points far out or not finite share the outermost cells instead of overflowing a cell index.
TEST(CellGrid, FarAndNonFiniteCoordinatesStayFindable) {
  CellGrid grid(1.75f);
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  grid.resize(4);
  grid.place(0, true, {1e30f, 0, 0});
  grid.place(1, true, {1e30f, 0, 0.5f});
  grid.place(2, true, {nan, -inf, 0});
  grid.place(3, true, {0, 0, 0});
  EXPECT_EQ(visited(grid, {inf, 0, 0}), (std::vector<sim::ModuleId>{0, 1}));
  EXPECT_EQ(visited(grid, {-1e38f, -1e38f, 0}), (std::vector<sim::ModuleId>{2}));
  EXPECT_EQ(visited(grid, {0.5f, 0, 0}), (std::vector<sim::ModuleId>{3}));
  grid.place(2, true, {0, 1, 0});
  EXPECT_EQ(visited(grid, {0.5f, 0, 0}), (std::vector<sim::ModuleId>{2, 3}));
  grid.place(0, false, {1e30f, 0, 0});
  EXPECT_EQ(visited(grid, {inf, 0, 0}), (std::vector<sim::ModuleId>{1}));
}

// A lattice's modules at rest in their cells are found from the lattice, not binned: on every kind
// of lattice, with modules leaving their cells, going away and coming back, the grid visits every
// present module within its side of a point, and bins only those away from their cells.
TEST(CellGrid, FindsModulesAtRestWithoutBinningThem) {
  using sim::LatticeKind;
  for (const sim::LatticeSpec spec :
       {sim::LatticeSpec{LatticeKind::Cubic, {6, 5, 4}}, sim::LatticeSpec{LatticeKind::Square2d, {9, 7, 1}},
        sim::LatticeSpec{LatticeKind::Hex2d, {8, 9, 1}}, sim::LatticeSpec{LatticeKind::Fcc, {5, 5, 6}},
        sim::LatticeSpec{LatticeKind::Line, {30, 1, 1}}, sim::LatticeSpec{LatticeKind::Ring, {24, 1, 1}}}) {
    SCOPED_TRACE(std::string(sim::lattice_name(spec.kind)));
    const sim::CellPose rest{spec, 1};
    const auto n = static_cast<sim::ModuleId>(spec.module_count());
    CellGrid grid(1.125f, rest);
    grid.resize(n);
    std::vector<sim::Vec3> at(n);
    std::vector<uint8_t> in(n, 1);
    for (sim::ModuleId m = 0; m < n; ++m) grid.place(m, true, at[m] = rest(m).position);
    // A ring's modules are all binned: the grid does not find them from their cells.
    EXPECT_EQ(grid.binned(), spec.kind == LatticeKind::Ring ? n : 0u);
    std::mt19937 random(11);
    std::uniform_real_distribution<float> step(-0.8f, 0.8f), coordinate(-2, 10);
    for (int round = 0; round < 4; ++round) {
      for (sim::ModuleId m = static_cast<sim::ModuleId>(round); m < n; m += 5) {
        if (round == 3) {  // back to its cell, or back in the grid there
          in[m] = 1;
          grid.place(m, true, at[m] = rest(m).position);
        } else if (round == 2 && m % 2 == 0) {
          in[m] = 0;
          grid.place(m, false, at[m]);
        } else if (in[m]) {
          at[m] = {at[m][0] + step(random), at[m][1] + step(random), at[m][2] + step(random)};
          grid.place(m, true, at[m]);
        }
      }
      size_t away = 0;
      for (sim::ModuleId m = 0; m < n; ++m) away += in[m] && at[m] != rest(m).position;
      if (spec.kind != LatticeKind::Ring) {
        EXPECT_EQ(grid.binned(), away) << "round " << round;
      }
      for (int probe = 0; probe < 100; ++probe) {
        const sim::Vec3 p{coordinate(random), coordinate(random), coordinate(random) * (spec.size[2] > 1 ? 1 : 0)};
        std::vector<sim::ModuleId> seen;
        grid.around(p, [&](sim::ModuleId m, const sim::Vec3& m_at) {
          seen.push_back(m);
          EXPECT_EQ(m_at, at[m]) << "module " << m;
        });
        std::sort(seen.begin(), seen.end());
        EXPECT_EQ(std::adjacent_find(seen.begin(), seen.end()), seen.end()) << "a module visited twice";
        for (sim::ModuleId m = 0; m < n; ++m) {
          const bool listed = std::binary_search(seen.begin(), seen.end(), m);
          if (!in[m]) {
            EXPECT_FALSE(listed) << "absent module " << m;
          } else {
            EXPECT_EQ(grid.at(m), at[m]);
            if (distance(at[m], p) <= grid.side()) {
              EXPECT_TRUE(listed) << "module " << m << " round " << round;
            }
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace dw::physics
