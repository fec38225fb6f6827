// `dwatch bench physics` as a user runs it (bench/bench_physics.cpp): each row of the comparison
// says what it measures, sets dwatch's physics step beside the plain Bullet program's and gives
// their ratio, and both sides do the same scene.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "tests/app/cli.h"

namespace {

using namespace dw::cli_test;

// A CSV line's cells; the first, quoted, is the row's label.
std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out;
  const size_t close = line.find("\",");
  out.push_back(line.substr(1, close - 1));
  std::istringstream rest(line.substr(close + 2));
  for (std::string cell; std::getline(rest, cell, ',');) out.push_back(cell);
  return out;
}

TEST_F(Cli, BenchPhysicsSetsEachRowBesidePlainBullet) {
  const Result r = run("bench physics --quick --size 3 --steps 10 --repeat 1 --out " + dir_.string());
  ASSERT_EQ(r.code, 0) << r.err;
  // What each row measures, in its name: unbonded, bonded cluster, latched.
  const std::vector<std::string> rows = {
      "unbonded: 27 boxes a cell apart, falling",
      "unbonded: 3^3 pile resting on the ground",
      "bonded cluster: 3^3 falling from 2 above the ground",
      "bonded cluster: 3^3 resting free on the ground",
      "latched: 3^3 to the ground, at rest",
  };
  EXPECT_NE(r.out.find("dwatch/Bullet"), std::string::npos) << r.out;
  for (const std::string& row : rows) {
    const size_t at = r.out.find(row);
    ASSERT_NE(at, std::string::npos) << row << "\n" << r.out;
    const std::string line = r.out.substr(at, r.out.find('\n', at) - at);
    EXPECT_EQ(line.back(), 'x') << line;  // the ratio, as 1.23x
    EXPECT_NE(r.out.find("kinetic energy", at), std::string::npos) << r.out;
  }
  // The rows as CSV: steps, modules, ms a step each side, the ratio, the first step, the end
  // figures and the peak memory.
  std::istringstream csv(slurp(dir_ / "physics.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line,
            "row,steps,modules,dwatch_ms_per_step,bullet_ms_per_step,ratio,dwatch_first_ms,bullet_first_ms,"
            "dwatch_energy_per_box,bullet_energy_per_box,dwatch_deepest,bullet_deepest,dwatch_drop,bullet_drop,"
            "dwatch_peak_mib,bullet_peak_mib");
  for (const std::string& row : rows) {
    ASSERT_TRUE(std::getline(csv, line)) << row;
    const std::vector<std::string> c = cells(line);
    ASSERT_EQ(c.size(), 16u) << line;
    EXPECT_EQ(c[0], row);
    const double mine = std::stod(c[3]), plain = std::stod(c[4]), ratio = std::stod(c[5]);
    EXPECT_GT(plain, 0) << line;
    EXPECT_NEAR(ratio, mine / plain, 1e-3 * ratio) << line;
    // Both do the same scene with the same settings: ten steps of free fall (1/6 s) take either as
    // far, about g t^2 / 2 (Bullet's integration overshoots it by up to 10%, less in substeps).
    if (row.find("falling") != std::string::npos) {
      EXPECT_NEAR(std::stod(c[12]), std::stod(c[13]), 1e-3) << line;
      EXPECT_NEAR(std::stod(c[13]), 9.81 / 36 / 2, 0.015) << line;
    }
  }
  EXPECT_FALSE(std::getline(csv, line)) << line;
  EXPECT_FALSE(fs::exists(dir_ / "physics_runtime.csv"));  // --quick: only the rows beside Bullet
}

}  // namespace
