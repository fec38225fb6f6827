// `dwatch replay` as a user meets it (app/cli/replay_command.cpp): a trace's matches, sorted,
// with their statistics; several watchpoints, the budget, the shapes; a recorded run's own
// watchpoints read from its trace.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tests/app/cli.h"

namespace {

using namespace dw::cli_test;

const fs::path kScenarios = DWATCH_SCENARIOS_DIR;

TEST_F(Cli, ReplayWritesSortedMatchesAndStats) {
  const fs::path c = cases_ / "02_leader_two_hop_hex";
  const Result r = run("replay " + (c / "trace.jsonl").string() + " --watch @" + (c / "watch.txt").string() +
                       " --algorithm centralized --matches " + (dir_ / "m.jsonl").string() + " --stats " +
                       (dir_ / "s.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream in(dir_ / "m.jsonl");
  std::vector<std::pair<int64_t, std::vector<int>>> rows;
  for (std::string line; std::getline(in, line);) {
    const auto j = nlohmann::ordered_json::parse(line);
    EXPECT_EQ(j["watch"], "02_leader_two_hop_hex");
    std::vector<int> ids;
    for (const auto& [k, v] : j["slots"].items()) ids.push_back(v.get<int>());
    rows.push_back({j["t"].get<int64_t>(), ids});
  }
  EXPECT_EQ(rows.size(), 385u);
  EXPECT_TRUE(std::is_sorted(rows.begin(), rows.end()));
  const auto stats = nlohmann::json::parse(slurp(dir_ / "s.json"));
  EXPECT_TRUE(stats["matches"].is_number_integer());
  EXPECT_EQ(stats["matches"].get<int>(), 385);
  EXPECT_EQ(stats["watches"][0]["per_step"].size(), 6u);
}

TEST_F(Cli, ReplayPrintsMatchesWhenNoFileIsGiven) {
  const fs::path c = cases_ / "07_last_last_single";
  const Result r = run("replay " + (c / "trace.jsonl").string() + " -w @" + (c / "watch.txt").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("07_last_last_single: 9 matches"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("t=2 a=2"), std::string::npos) << r.out;
}

TEST_F(Cli, SeveralWatchesAtOnce) {
  const fs::path c = cases_ / "01_fig6_2222_grid";
  const Result r = run("replay " + (c / "trace.jsonl").string() + " -w @" + (c / "watch.txt").string() +
                       " -w 'ones=modules(a); (a.x1 = 1)' --matches " + (dir_ / "m.jsonl").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string m = slurp(dir_ / "m.jsonl");
  EXPECT_NE(m.find("\"watch\":\"ones\""), std::string::npos);
  EXPECT_NE(m.find("\"watch\":\"01_fig6_2222_grid\""), std::string::npos);
  // Two of one name, as two [[watch]] of one name in a scenario, are refused: matches name them.
  expect_refused(
      "replay " + (c / "trace.jsonl").string() + " -w 'w=modules(a); (a.x1 = 1)' -w 'w=modules(a); (a.x1 = 0)'",
      "<watch 2>:1:1: error: a second watchpoint named \"w\"\n");
}

TEST_F(Cli, BadTraceLineIsBadInputNamingTheLine) {
  const fs::path t =
      write("t.jsonl", "{\"t\":0,\"m\":0,\"vars\":{},\"nbrs\":[]}\n{\"t\":0,\"m\":0,\"vars\":{},\"nbrs\":[]}\n");
  const Result r = run("replay " + t.string() + " -w 'modules(a); (a.x = 1)'");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, t.string() + ":2:1: error: duplicate line for module 0 at step 0 (first at line 1)\n");
}

TEST_F(Cli, BudgetStopsWithExitOneAndKeepsWhatWasFound) {
  const fs::path c = cases_ / "10_five_slots_negative";
  const Result r = run("replay " + (c / "trace.jsonl").string() + " -w @" + (c / "watch.txt").string() +
                       " -a centralized --max-live 4100 --matches " + (dir_ / "m.jsonl").string());
  EXPECT_EQ(r.code, 1);
  // Step 0 fills 4,052 PatternMatchers, step 1 4,245: its 921 matches are kept, none of step 1's.
  EXPECT_NE(r.err.find("stopped: more than 4100 PatternMatchers at watch step 1"), std::string::npos) << r.err;
  const std::string m = slurp(dir_ / "m.jsonl");
  EXPECT_EQ(std::count(m.begin(), m.end(), '\n'), 921);
  EXPECT_EQ(m.find("\"t\":1"), std::string::npos) << "the step that went over reports nothing";
}

// A trace recorded by run lists its watchpoints with their readings and actions: replay with no
// --watch finds exactly the run's matches, whatever each reading (centralized, distributed,
// simultaneous, count, actions), and says when the header lists none.
TEST_F(Cli, ReplayOfARecordedRunWithoutWatchFindsTheRunsMatches) {
  std::string toml = slurp(kScenarios / "leader_election.toml");
  toml.replace(toml.find("action = \"pause\""), 16, "action = \"log\"");
  toml +=
      "[[watch]]\nname = \"close\"\ntext = \"modules(a b); (a.isLeader = 1) and (b.isLeader = 0)\"\n"
      "algorithm = \"centralized\"\nshape = \"any\"\n"
      "[[watch]]\nname = \"simultaneous\"\ntext = \"modules(a b c); (a.isLeader = 1) and (c.isLeader = 1)\"\n"
      "states = \"simultaneous\"\nshape = \"ordered\"\n"
      "[[watch]]\nname = \"counted\"\ntext = \"modules(a); a.isLeader = 0\"\naction = \"count\"\n";
  const fs::path scenario = write("mixed.toml", toml);
  const fs::path trace = dir_ / "t.jsonl", live = dir_ / "live.jsonl", replayed = dir_ / "replayed.jsonl";
  const Result r = run("run " + scenario.string() + " --no-progress --steps 15 --record " + trace.string() +
                       " --matches " + live.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const Result p = run("replay " + trace.string() + " --matches " + replayed.string());
  ASSERT_EQ(p.code, 0) << p.err;
  EXPECT_NE(p.out.find("each watchpoint read as the run that recorded the trace read it"), std::string::npos) << p.out;
  EXPECT_NE(p.out.find("close [centralized, any groups]"), std::string::npos) << p.out;
  EXPECT_GT(slurp(live).size(), 1000u);
  EXPECT_NE(slurp(live).find("\"watch\":\"simultaneous\""), std::string::npos);
  EXPECT_NE(slurp(live).find("{\"watch\":\"counted\",\"counted\":"), std::string::npos);
  EXPECT_EQ(slurp(live), slurp(replayed));
  // A trace that lists no watchpoint needs --watch.
  const fs::path bare = write("bare.jsonl", "{\"t\":0,\"m\":0,\"vars\":{\"x\":1},\"nbrs\":[]}\n");
  const Result none = run("replay " + bare.string());
  EXPECT_EQ(none.code, 2);
  EXPECT_NE(none.err.find("the trace's header lists no watchpoints"), std::string::npos) << none.err;
}

// A run a pause stopped did not decide its last steps: its trace says so in its last line, and
// replay of its own watchpoints finds exactly its matches; the same watchpoint given with --watch
// decides them, as at the end of any trace, and finds more.
TEST_F(Cli, ReplayOfARunAPauseStoppedFindsTheRunsMatches) {
  std::string toml = slurp(kScenarios / "leader_election.toml");
  toml += "[[watch]]\nname = \"near\"\ntext = \"modules(a b); (a.isLeader = 0) and (b.isLeader = 0)\"\n";
  const fs::path scenario = write("paused.toml", toml);
  const fs::path trace = dir_ / "t.jsonl", live = dir_ / "live.jsonl", replayed = dir_ / "replayed.jsonl",
                 drained = dir_ / "drained.jsonl";
  const Result r =
      run("run " + scenario.string() + " --no-progress --record " + trace.string() + " --matches " + live.string());
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_NE(r.out.find("PAUSED"), std::string::npos) << r.out;
  const std::string text = slurp(trace);
  EXPECT_EQ(text.substr(text.rfind('\n', text.size() - 2) + 1, 32), "{\"paused\":{\"watch\":\"two_leaders\"");
  const Result p = run("replay " + trace.string() + " --matches " + replayed.string());
  ASSERT_EQ(p.code, 0) << p.err;
  EXPECT_NE(p.out.find("the run stopped at two_leaders's pause"), std::string::npos) << p.out;
  EXPECT_GT(slurp(live).size(), 100u);
  EXPECT_EQ(slurp(live), slurp(replayed));
  const Result d = run("replay " + trace.string() + " --watch 'near=modules(a b); (a.isLeader = 0) and " +
                       "(b.isLeader = 0)' --matches " + drained.string());
  ASSERT_EQ(d.code, 0) << d.err;
  const auto lines = [](const std::string& s) { return std::count(s.begin(), s.end(), '\n'); };
  const std::string near_live = [&] {
    std::string out, all = slurp(live);
    for (size_t at = 0, end; (end = all.find('\n', at)) != std::string::npos; at = end + 1)
      if (all.compare(at, 16, "{\"watch\":\"near\"") == 0) out += all.substr(at, end - at + 1);
    return out;
  }();
  EXPECT_GT(lines(slurp(drained)), lines(near_live)) << "drained, the last steps are decided";
}

// `replay --shape S --states simultaneous` on a shapes conformance case writes as many matches as
// the reference; a shape the paper's reading cannot find is bad input.
TEST_F(ShapesCli, ReplayFindsEveryShapeAndRefusesWhatTheReadingCannotFind) {
  const fs::path c = fs::path(DWATCH_CONFORMANCE_DIR).parent_path() / "conformance_shapes" / "s01_star_hex_static";
  for (const char* shape : {"chain", "ordered", "any"}) {
    for (const char* reading : {"--algorithm centralized", "--algorithm distributed --states simultaneous"}) {
      const fs::path out = dir_ / (std::string(shape) + ".jsonl");
      const Result r = run("replay " + (c / "trace.jsonl").string() + " --watch @" + (c / "watch.txt").string() +
                           " --shape " + shape + " " + reading + " --matches " + out.string());
      ASSERT_EQ(r.code, 0) << r.err;
      const std::string want = slurp(c / ("expected." + std::string(shape) + ".jsonl")), got = slurp(out);
      EXPECT_EQ(std::count(got.begin(), got.end(), '\n'), std::count(want.begin(), want.end(), '\n'))
          << shape << " " << reading;
    }
  }
  const Result refused = run("replay " + (c / "trace.jsonl").string() + " --watch @" + (c / "watch.txt").string() +
                             " --algorithm distributed --shape any");
  EXPECT_EQ(refused.code, 2);
  EXPECT_NE(refused.err.find("shape \"any\" needs states = \"simultaneous\""), std::string::npos) << refused.err;
  EXPECT_EQ(run("replay " + (c / "trace.jsonl").string() + " --watch x --shape star").code, 2);
}

}  // namespace
