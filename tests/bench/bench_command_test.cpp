// `dwatch bench` as a user meets it (bench/bench_command.cpp): a bench's CSV file, and the
// detector flags as the runtime benches read them.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "tests/app/cli.h"

namespace {

using namespace dw::cli_test;

TEST_F(Cli, BenchTable1WritesItsCsv) {
  const Result r =
      run("bench table1 --size 4 --steps 6 --repeat 1 --tuple 2:2:2:2 --tuple 1:1:1:1 --out " + dir_.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string csv = slurp(dir_ / "table1.csv");
  EXPECT_NE(csv.find("\"2:2:2:2\","), std::string::npos) << csv;
  EXPECT_NE(csv.find("\"1:1:1:1\","), std::string::npos) << csv;
}

// The runtime benchmarks read the watch as the detector flags say.
TEST_F(Cli, RuntimeBenchesHonourTheDetectorFlags) {
  // The row of a table1 CSV file: matches, created, messages, best, median, peak MiB, stopped.
  auto row = [](const fs::path& csv) {
    std::istringstream in(slurp(csv));
    std::string line;
    std::getline(in, line);  // the header
    std::getline(in, line);
    std::vector<std::string> cells;
    std::istringstream fields(line);
    for (std::string cell; std::getline(fields, cell, ',');) cells.push_back(cell);
    return cells;
  };
  const std::string table1 = "bench table1 --size 4 --steps 6 --repeat 1 --tuple 2:2:2:2 --out ";
  ASSERT_EQ(run(table1 + (dir_ / "paper").string()).code, 0);
  ASSERT_EQ(run(table1 + (dir_ / "late").string() + " --no-early-termination").code, 0);
  const auto paper = row(dir_ / "paper" / "table1.csv"), late = row(dir_ / "late" / "table1.csv");
  ASSERT_EQ(paper.size(), 8u);
  ASSERT_EQ(late.size(), 8u);
  EXPECT_EQ(late[1], paper[1]);                            // the same matches
  EXPECT_GT(std::stoull(late[2]), std::stoull(paper[2]));  // from more PatternMatchers
  EXPECT_EQ(paper[7], "0");

  const Result budget = run(table1 + (dir_ / "budget").string() + " --max-live 10");
  EXPECT_EQ(budget.code, 1);
  EXPECT_NE(budget.out.find("stopped at the --max-live budget"), std::string::npos) << budget.out;
  EXPECT_EQ(row(dir_ / "budget" / "table1.csv")[7], "1");
}

}  // namespace
