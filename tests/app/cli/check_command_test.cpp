// `dwatch check` as a user meets it (app/cli/check_command.cpp): a watchpoint explained, its
// mistakes with carets, each reading's lag.
#include <gtest/gtest.h>

#include "tests/app/cli.h"

namespace {

using namespace dw::cli_test;

TEST_F(Cli, CheckExplainsAValidWatchpoint) {
  const Result r = run("check 'modules(a b c);(a.isLeader = 1) and (c.next.isLeader = 1)'");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("E+             1"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("isLeader: offsets 0, 1, temporal span 1"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("b: nothing (a connector)"), std::string::npos) << r.out;
}

TEST_F(Cli, CheckReportsEveryMistakeWithCaretsAndExitsTwo) {
  const fs::path f = write("bad.watch", "modules(a b);\n(a.x = 1) and (c.y = 2)\n");
  const Result r = run("check @" + f.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, f.string() +
                       ":2:16: error: module 'c' is not declared in modules(a b)\n"
                       "(a.x = 1) and (c.y = 2)\n"
                       "               ^\n");
}

TEST_F(Cli, MissingWatchFileIsBadInput) {
  const Result r = run("check @" + (dir_ / "none.watch").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("No such file or directory (the watchpoint file)"), std::string::npos) << r.err;
}

TEST_F(ShapesCli, CheckStatesEachReadingsLag) {
  const Result r = run("check 'modules(a b c d); (a.x = 1) and (b.next.x = 0)'");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("lag E+ = 1"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("lag E+ + k - 1 = 4"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("L = k - 1 = 3 hops for chain, k(k - 1)/2 = 6 for ordered and any; lag E+ + L = 4 / 7"),
            std::string::npos)
      << r.out;
}

}  // namespace
