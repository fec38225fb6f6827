#include "physics/cell_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace dw::physics {
namespace {

std::vector<sim::ModuleId> visited(const CellGrid& grid, const sim::Vec3& at) {
  std::vector<sim::ModuleId> out;
  grid.around(at, [&](sim::ModuleId m) { out.push_back(m); });
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
  for (sim::ModuleId m = 0; m < at.size(); ++m) grid.insert(m, at[m] = point());
  for (int round = 0; round < 3; ++round) {
    for (sim::ModuleId m = 0; m < at.size(); m += 3) {
      if (!in[m]) continue;
      const sim::Vec3 to = point();
      grid.move(m, at[m], to);
      at[m] = to;
    }
    for (sim::ModuleId m = static_cast<sim::ModuleId>(round); m < at.size(); m += 7)
      if (in[m]) {
        grid.erase(m, at[m]);
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
  grid.insert(0, {1e30f, 0, 0});
  grid.insert(1, {1e30f, 0, 0.5f});
  grid.insert(2, {nan, -inf, 0});
  grid.insert(3, {0, 0, 0});
  EXPECT_EQ(visited(grid, {inf, 0, 0}), (std::vector<sim::ModuleId>{0, 1}));
  EXPECT_EQ(visited(grid, {-1e38f, -1e38f, 0}), (std::vector<sim::ModuleId>{2}));
  EXPECT_EQ(visited(grid, {0.5f, 0, 0}), (std::vector<sim::ModuleId>{3}));
  grid.move(2, {nan, -inf, 0}, {0, 1, 0});
  EXPECT_EQ(visited(grid, {0.5f, 0, 0}), (std::vector<sim::ModuleId>{2, 3}));
  grid.erase(0, {1e30f, 0, 0});
  EXPECT_EQ(visited(grid, {inf, 0, 0}), (std::vector<sim::ModuleId>{1}));
}

}  // namespace
}  // namespace dw::physics
