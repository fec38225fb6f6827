// Zero-slot watchpoints (docs/design.md §4c) as a user meets them on the command line: `run` and
// `replay` list their matches as rows with no module, every reading alike; `check` explains them
// and refuses an action on them.
#include <gtest/gtest.h>

#include <string>

#include "tests/app/cli.h"

namespace {

using namespace dw::cli_test;

const fs::path kScenarios = DWATCH_SCENARIOS_DIR;

// One line a step from `first` to `last`, as the matches file writes a zero-slot watchpoint's.
std::string rows(const std::string& watch, int first, int last) {
  std::string s;
  for (int t = first; t <= last; ++t)
    s += "{\"watch\":\"" + watch + "\",\"t\":" + std::to_string(t) + ",\"slots\":{}}\n";
  return s;
}

TEST_F(Cli, ZeroSlotMatchesAreRowsWithNoModuleInEveryReadingAndInReplay) {
  const std::string scenario = (kScenarios / "one_token_ring.toml").string();
  const std::string want = rows("not_one_token", 21, 39);
  for (const char* reading : {"--algorithm centralized", "--algorithm centralized --shape any",
                              "--algorithm distributed", "--algorithm distributed --states simultaneous --shape any"}) {
    const fs::path matches = dir_ / "m.jsonl", trace = dir_ / "t.jsonl", replayed = dir_ / "r.jsonl";
    const Result r =
        run("run " + scenario + " " + reading + " --record " + trace.string() + " --matches " + matches.string());
    ASSERT_EQ(r.code, 0) << reading << ": " << r.err;
    EXPECT_EQ(slurp(matches), want) << reading;
    const Result p = run("replay " + trace.string() + " --matches " + replayed.string());
    ASSERT_EQ(p.code, 0) << reading << ": " << p.err;
    EXPECT_EQ(slurp(replayed), want) << reading;
  }
  // Without a matches file the summary lists the first matches, each a step with no module.
  const Result listed = run("run " + scenario);
  ASSERT_EQ(listed.code, 0) << listed.err;
  EXPECT_NE(listed.out.find("19 matches\n    t=21 (no module)\n    t=22 (no module)\n"), std::string::npos)
      << listed.out;
}

TEST_F(Cli, CheckExplainsAZeroSlotWatchpointAndRefusesItsAction) {
  const Result r = run("check 'modules(); count(n in all: n.token = 1) != 1'");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("zero-slot watchpoint on the whole ensemble"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("every reading alike"), std::string::npos) << r.out;
  const Result bad = run("check 'modules(); 1 = 1 then remove a'");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("has no module to act on"), std::string::npos) << bad.err;
}

}  // namespace
