// `dwatch bench paper` as a user runs it: the files it writes, their numbers checked against what
// they must be, the plots, and its mistakes. (bench_paper.cpp; paper_report_test.cpp checks the
// verdicts and paper.md's text.)
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <vector>

#include "tests/app/cli.h"

namespace {

using namespace dw::cli_test;

// A CSV file as rows of column name -> text.
std::vector<std::map<std::string, std::string>> read_csv(const fs::path& p) {
  std::istringstream in(slurp(p));
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::istringstream fields(line);
    for (std::string cell; std::getline(fields, cell, ',');) cells.push_back(cell);
    if (header.empty()) {
      header = cells;
      continue;
    }
    EXPECT_EQ(cells.size(), header.size()) << line;
    std::map<std::string, std::string> row;
    for (size_t i = 0; i < cells.size() && i < header.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

// The connected sets of four modules of an n^3 cube with face neighbours, by brute force over
// every set of four.
uint64_t connected_fours(int n) {
  const int m = n * n * n;
  auto adjacent = [n](int a, int b) {
    const int ax = a % n, ay = a / n % n, az = a / (n * n), bx = b % n, by = b / n % n, bz = b / (n * n);
    return std::abs(ax - bx) + std::abs(ay - by) + std::abs(az - bz) == 1;
  };
  uint64_t count = 0;
  for (int a = 0; a < m; ++a)
    for (int b = a + 1; b < m; ++b)
      for (int c = b + 1; c < m; ++c)
        for (int d = c + 1; d < m; ++d) {
          const std::array<int, 4> s{a, b, c, d};
          int reached = 1;  // a bitmask over s, grown from s[0]
          for (bool grew = true; grew;) {
            grew = false;
            for (int i = 0; i < 4; ++i)
              for (int j = 0; j < 4; ++j)
                if ((reached >> i & 1) && !(reached >> j & 1) && adjacent(s[i], s[j])) reached |= 1 << j, grew = true;
          }
          if (reached == 15) ++count;
        }
  return count;
}

class BenchPaper : public Cli {
 protected:
  // One small run shared by the tests below: a 4^3 cube, 8 steps.
  static void SetUpTestSuite() {
    out_ = fs::temp_directory_path() / ("dwatch_bench_paper_" + std::to_string(::getpid()));
    const std::string cmd = std::string(DWATCH_EXE) + " bench paper --size 4 --steps 8 --repeat 1 --quick --out " +
                            out_.string() + " >" + (out_.string() + ".out") + " 2>&1";
    status_ = std::system(cmd.c_str());
  }
  static void TearDownTestSuite() {
    fs::remove_all(out_);
    fs::remove(out_.string() + ".out");
  }
  void SetUp() override {
    Cli::SetUp();
    ASSERT_TRUE(WIFEXITED(status_) && WEXITSTATUS(status_) == 0) << slurp(out_.string() + ".out");
  }
  static inline fs::path out_;
  static inline int status_ = -1;
};

TEST_F(BenchPaper, TableOneCountsEachReadingAsItMustBe) {
  const auto rows = read_csv(out_ / "table1.csv");
  ASSERT_EQ(rows.size(), 5u);
  const uint64_t groups = connected_fours(4);  // per step
  for (const auto& r : rows) {
    SCOPED_TRACE(r.at("tuple"));
    EXPECT_EQ(r.at("modules"), "64");
    EXPECT_EQ(r.at("steps"), "8");
    const uint64_t matches = std::stoull(r.at("matches")), chain_sets = std::stoull(r.at("chain_sets"));
    const uint64_t matched_groups = std::stoull(r.at("groups_matched"));
    EXPECT_GT(chain_sets, 0u);
    EXPECT_LE(chain_sets, matches);         // a set counted once however many chains match it
    EXPECT_LE(matched_groups, groups * 8);  // each connected group at most once a step
    EXPECT_GE(std::stod(r.at("best_seconds")), 0);
    double p = 1;
    std::istringstream tuple(r.at("tuple"));
    for (std::string m; std::getline(tuple, m, ':');) p /= std::stod(m);
    EXPECT_NEAR(std::stod(r.at("one_per_group")), std::round(double(groups) * 8 * p), 0.5);
  }
  // With every x_i = 0 every connected group matches at every step; a chain of four is matched
  // by its two directions, a square by eight.
  EXPECT_EQ(rows[0].at("tuple"), "1:1:1:1");
  EXPECT_EQ(std::stoull(rows[0].at("groups_matched")), groups * 8);
  EXPECT_EQ(rows[0].at("paper_matches"), "6233141");
  EXPECT_EQ(rows[0].at("paper_seconds"), "715");
}

TEST_F(BenchPaper, FigureSevenIsTheEnginesCountBySlotsFilled) {
  const auto rows = read_csv(out_ / "fig7.csv");
  ASSERT_EQ(rows.size(), 5u * 2 * 4);
  const auto table1 = read_csv(out_ / "table1.csv");
  for (const auto& r : rows) {
    // Every module starts one PatternMatcher a step; every match filled four slots, and with
    // every x_i = 0 every four-filled PatternMatcher is a match.
    if (r.at("filled") == "1") {
      EXPECT_EQ(r.at("created"), "512") << r.at("tuple");
    }
    if (r.at("filled") == "4" && r.at("algorithm") == "distributed") {
      const auto t =
          std::find_if(table1.begin(), table1.end(), [&](const auto& x) { return x.at("tuple") == r.at("tuple"); });
      ASSERT_NE(t, table1.end());
      EXPECT_GE(std::stoull(r.at("created")), std::stoull(t->at("matches"))) << r.at("tuple");
      if (r.at("tuple") == "1:1:1:1") {
        EXPECT_EQ(r.at("created"), t->at("matches"));
      }
    }
  }
}

TEST_F(BenchPaper, FigureEightHasEverySizeAndItsFit) {
  const auto rows = read_csv(out_ / "fig8.csv");
  ASSERT_EQ(rows.size(), 4u * 3);  // planes 1..4 of 4 x 4, three series
  std::set<std::string> modules;
  for (const auto& r : rows) {
    EXPECT_EQ(std::stoi(r.at("modules")), 16 * std::stoi(r.at("planes")));
    modules.insert(r.at("modules"));
    const double r2 = std::stod(r.at("r_squared"));
    EXPECT_TRUE(r2 <= 1 && r2 > -10) << r2;
    if (r.at("series") == "no watchpoint") {
      EXPECT_EQ(r.at("matches"), "0");
    } else if (r.at("planes") == "4") {
      EXPECT_NE(r.at("matches"), "0");
    }
  }
  EXPECT_EQ(modules, (std::set<std::string>{"16", "32", "48", "64"}));
}

TEST_F(BenchPaper, TableTwoSetsEachOverheadBesideThePapers) {
  const auto rows = read_csv(out_ / "table2.csv");
  ASSERT_EQ(rows.size(), 15u);
  for (const auto& r : rows) {
    const double overhead = 100 * (std::stod(r.at("best_seconds")) / std::stod(r.at("baseline_seconds")) - 1);
    EXPECT_NEAR(std::stod(r.at("overhead_percent")), overhead, 1e-6 * std::max(1.0, std::abs(overhead)));
    EXPECT_EQ(r.at("workload"), "random_vars");
  }
  EXPECT_EQ(rows.back().at("size"), "5");
  EXPECT_EQ(rows.back().at("frequency"), "high");
  EXPECT_EQ(rows.back().at("paper_overhead_percent"), "1432.5");
}

TEST_F(BenchPaper, DrawsEveryPlotAndWritesThePaperMarkdown) {
  for (const char* png : {"table1.png", "fig7.png", "fig8.png", "table2.png"})
    EXPECT_EQ(png_size(out_ / png), std::make_pair(960u, 624u)) << png;
  const std::string md = slurp(out_ / "paper.md");
  for (const char* section : {"## Verdicts", "## Table I", "### Which count is the paper's", "## Fig. 7", "## Fig. 8",
                              "## Table II", "![Table I](table1.png)", "dwatch bench paper --out "})
    EXPECT_NE(md.find(section), std::string::npos) << section;
  const std::string console = slurp(out_.string() + ".out");
  EXPECT_NE(console.find("The paper's claims:"), std::string::npos) << console;
}

TEST_F(Cli, BenchPaperMistakesAreBadInput) {
  EXPECT_EQ(run("bench paper --table2-workload physics").code, 2);
  const Result r = run("bench paper --size 3 --tuple 1:x --out " + (dir_ / "p").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("tuple '1:x' is not four positive integers"), std::string::npos) << r.err;
  write("file", "");
  EXPECT_EQ(run("bench paper --out " + (dir_ / "file").string()).code, 2);
}

}  // namespace
