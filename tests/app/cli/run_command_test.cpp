// `dwatch run` as a user meets it (app/cli/run_command.cpp): pauses and rollbacks, the budget,
// recorded runs replayed to the same matches, state hashes, statistics, the drain.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/app/cli.h"

namespace {

using namespace dw::cli_test;

const fs::path kScenarios = DWATCH_SCENARIOS_DIR;

std::string line_with(const std::string& text, const std::string& what) {
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.find(what) != std::string::npos) return line;
  return "";
}

// run takes the budget too, for every watchpoint of the scenario; a missing value is named.
TEST_F(Cli, RunTakesThePatternMatcherBudgetForEveryWatchpoint) {
  const std::string scenario = (fs::path(DWATCH_SCENARIOS_DIR) / "token_ring.toml").string();
  const Result r = run("run " + scenario + " --max-live 10");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("stopped: more than 10 PatternMatchers at watch step 0"), std::string::npos) << r.err;
  EXPECT_EQ(run("run " + scenario).code, 0);
  const Result missing = run("run " + scenario + " --max-live");
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.err.find("--max-live: 1 required"), std::string::npos) << missing.err;
}

TEST_F(Cli, RunPausesOnTheFig2ViolationAndRollsBackToIt) {
  const Result r = run("run " + (kScenarios / "leader_election.toml").string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("two_leaders [distributed, pause]"), std::string::npos) << r.out;
  const std::string paused = line_with(r.out, "PAUSED at step ");
  ASSERT_FALSE(paused.empty()) << r.out;
  EXPECT_NE(r.out.find("rolled back to step"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("state hash: 0x"), std::string::npos);
}

TEST_F(Cli, RunOfTheCorrectScenariosFindsNothing) {
  for (const char* name : {"leader_election_correct.toml", "token_ring_correct.toml"}) {
    const Result r = run("run " + (kScenarios / name).string());
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find(": 0 matches"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("PAUSED"), std::string::npos) << r.out;
  }
}

TEST_F(Cli, RecordedRunReplaysToTheSameMatches) {
  std::string toml = slurp(kScenarios / "leader_election.toml");
  toml.replace(toml.find("action = \"pause\""), 16, "action = \"log\"");
  const fs::path scenario = write("le.toml", toml);
  const std::string text = "two_leaders='modules(a b c); (a.isLeader = 1) and (c.isLeader = 1)'";
  for (const char* algorithm : {"distributed", "centralized"}) {
    const fs::path trace = dir_ / "t.jsonl", live = dir_ / "live.jsonl", replayed = dir_ / "replayed.jsonl";
    const Result r = run("run " + scenario.string() + " --steps 30 --threads 2 --algorithm " + algorithm +
                         " --record " + trace.string() + " --matches " + live.string());
    ASSERT_EQ(r.code, 0) << r.err;
    const Result p = run("replay " + trace.string() + " --watch " + text + " --algorithm " + algorithm + " --matches " +
                         replayed.string());
    ASSERT_EQ(p.code, 0) << p.err;
    EXPECT_GT(slurp(live).size(), 100u);
    EXPECT_EQ(slurp(live), slurp(replayed)) << algorithm;
  }
}

// docs/design.md §4b: an aggregate over neighbours' values and an action; replay of the run's trace finds
// the run's matches, those of the last steps included (the agents' hop drained at the end), and
// performs no action, saying so.
TEST_F(Cli, RecordedRunWithAggregatesAndActionsReplaysToTheSameMatches) {
  std::string toml = slurp(kScenarios / "leader_election.toml");
  toml.replace(toml.find("action = \"pause\""), 16, "action = \"log\"");
  const std::string text = "modules(a b); count(n in neighbors(a): n.isLeader = 1) >= 1 and b.isLeader = 0";
  const std::string fig2 = "modules(a b c); (a.isLeader = 1) and (c.isLeader = 1)";
  toml.replace(toml.find(fig2), fig2.size(), text + " then set b._priority = 0");
  const fs::path scenario = write("agg.toml", toml);
  for (const char* algorithm : {"distributed", "centralized"}) {
    const fs::path trace = dir_ / "t.jsonl", live = dir_ / "live.jsonl", replayed = dir_ / "replayed.jsonl";
    const Result r = run("run " + scenario.string() + " --steps 12 --threads 2 --algorithm " + algorithm +
                         " --record " + trace.string() + " --matches " + live.string());
    ASSERT_EQ(r.code, 0) << r.err;
    const Result p = run("replay " + trace.string() + " --watch 'two_leaders=" + text + " then set b._priority = 0'" +
                         " --algorithm " + algorithm + " --matches " + replayed.string());
    ASSERT_EQ(p.code, 0) << p.err;
    EXPECT_NE(p.err.find("performs none"), std::string::npos) << p.err;
    EXPECT_GT(slurp(live).size(), 100u);
    EXPECT_EQ(slurp(live), slurp(replayed)) << algorithm;
    // The last step each reading decides: 11, or 10 for a chain of two filled a step apart.
    const std::string last = std::string("\"t\":") + (algorithm == std::string("distributed") ? "10" : "11");
    EXPECT_NE(slurp(live).find(last), std::string::npos) << "the last step decided: " << algorithm;
  }
}

TEST_F(Cli, RunGivesTheSameStateHashOnAnyThreadCount) {
  const std::string scenario = (kScenarios / "aggregation_routing.toml").string();
  const std::string one = line_with(run("run " + scenario + " --steps 40 --threads 1").out, "state hash");
  const std::string two = line_with(run("run " + scenario + " --steps 40 --threads 2").out, "state hash");
  const std::string three = line_with(run("run " + scenario + " --steps 40 --threads 3").out, "state hash");
  ASSERT_FALSE(one.empty());
  EXPECT_EQ(one, two);
  EXPECT_EQ(one, three);
  EXPECT_NE(one, line_with(run("run " + scenario + " --steps 41").out, "state hash"));
}

// docs/design.md §7: one simulation watched two ways shares the simulation hash; the state hash
// and the watchpoints hash tell the two apart.
TEST_F(Cli, TheSimulationHashIsTheSameUnderOtherWatchpoints) {
  const std::string head =
      "name = \"le\"\nsteps = 30\nseed = 1\n[lattice]\nkind = \"hex2d\"\nsize = [12, 10]\n"
      "[[program]]\nname = \"leader_election\"\nbug = true\n";
  const auto watched = [&](const std::string& name, const std::string& text, const std::string& algorithm) {
    return write(name, head + "[[watch]]\nname = \"w\"\ntext = \"" + text + "\"\nalgorithm = \"" + algorithm +
                           "\"\naction = \"log\"\n");
  };
  const auto part = [](const std::string& line, const std::string& name) {
    const size_t at = line.find(name + " 0x");
    return at == std::string::npos ? std::string() : line.substr(at + name.size() + 1, 18);
  };
  const auto hash_line = [&](const fs::path& scenario) {
    return line_with(run("run " + scenario.string()).out, "state hash");
  };
  const std::string two =
      hash_line(watched("two.toml", "modules(a b c); (a.isLeader = 1) and (c.isLeader = 1)", "distributed"));
  const std::string one = hash_line(watched("one.toml", "modules(a); a.isLeader = 1", "centralized"));
  const std::string none = hash_line(write("none.toml", head));
  ASSERT_EQ(part(two, "simulation").size(), 18u) << two;
  EXPECT_EQ(part(two, "simulation"), part(one, "simulation"));
  EXPECT_EQ(part(two, "simulation"), part(none, "simulation"));
  EXPECT_NE(part(two, "watchpoints"), part(one, "watchpoints"));
  EXPECT_NE(part(two, "hash:"), part(one, "hash:"));
  EXPECT_NE(part(one, "hash:"), part(none, "hash:"));
  // A different simulation has a different simulation hash.
  const std::string seed2 = line_with(run("run " + (dir_ / "none.toml").string() + " --seed 2").out, "state hash");
  EXPECT_NE(part(none, "simulation"), part(seed2, "simulation"));
  // The run hash covers every step's simulation hash (issue 62, 10): the same under other
  // watchpoints and on other thread counts, printed and in --stats.
  const auto run_hash = [&](const std::string& args) {
    return part(line_with(run("run " + args).out, "run hash"), "hash:");
  };
  const std::string chained = run_hash((dir_ / "none.toml").string());
  ASSERT_EQ(chained.size(), 18u);
  EXPECT_EQ(run_hash((dir_ / "two.toml").string() + " -j 3 --stats " + (dir_ / "s.json").string()), chained);
  EXPECT_NE(run_hash((dir_ / "none.toml").string() + " --seed 2"), chained);
  EXPECT_NE(slurp(dir_ / "s.json").find("\"run_hash\": \"" + chained + "\""), std::string::npos);
}

TEST_F(Cli, RunOfABadScenarioIsBadInputWithFileLineColumn) {
  const fs::path f = write(
      "bad.toml", "[lattice]\nkind = \"hex2d\"\nsize = [4, 4]\n[[program]]\nname = \"leader_election\"\nbugs = 1\n");
  const Result r = run("run " + f.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err.rfind(f.string() + ":6:1: error: unknown key 'bugs' in [[program]] leader_election", 0), 0u) << r.err;
  EXPECT_EQ(run("run " + (dir_ / "missing.toml").string()).code, 2);
  EXPECT_EQ(run("run " + (kScenarios / "table1.toml").string() + " --record /nonexistent/dir/t.jsonl").code, 2);
}

TEST_F(Cli, RunWritesStatsAsJson) {
  const fs::path stats = dir_ / "s.json";
  const Result r = run("run " + (kScenarios / "token_ring.toml").string() + " --stats " + stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(slurp(stats));
  EXPECT_EQ(j["modules"], 16);
  EXPECT_EQ(j["pause"]["t"], 41);
  EXPECT_EQ(j["watches"][0]["matches"], 2);
  EXPECT_EQ(j["matches"], 2);
}

// A run drains its simultaneous-state watchpoints: the last steps are decided as a replay of its
// trace decides them, with the same matches.
TEST_F(ShapesCli, RunDrainsAndEqualsTheReplayOfItsTrace) {
  const std::string scenario = std::string(DWATCH_SCENARIOS_DIR) + "/token_ring_distributed.toml";
  const fs::path trace = dir_ / "t.jsonl", live = dir_ / "live.jsonl", replayed = dir_ / "replayed.jsonl";
  const std::string fig3 =
      "'modules(a x b); neighbor(x b) and (x.token = 1) and (((a.last.token = 1) and (b.last.token = 1)) or "
      "((a.last.token = 0) and (b.last.token = 0)))'";
  const Result r = run("run " + scenario + " --steps 42 --record " + trace.string() + " --matches " + live.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const Result p = run("replay " + trace.string() + " --watch token_from_nowhere=" + fig3 +
                       " --algorithm distributed --states simultaneous --matches " + replayed.string());
  ASSERT_EQ(p.code, 0) << p.err;
  EXPECT_NE(slurp(live).find("\"t\":41"), std::string::npos) << "step 41 is the last step: decided by the drain";
  auto ts = [](const std::string& text) {
    std::vector<std::string> lines;
    std::stringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line.substr(0, line.find("\"detected\"")));
    return lines;
  };
  EXPECT_EQ(ts(slurp(live)), ts(slurp(replayed)));
}

}  // namespace
