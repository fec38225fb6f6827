// The dwatch executable as a user meets it: exit codes, diagnostics on stderr, files written.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "render/image.h"
#include "tests/app/cli.h"
#include "tests/render/decoded_video.h"

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

// A session script piped in from a file is an input too: neither its name nor the standard input's
// may be recorded over.
TEST_F(Cli, ASessionScriptPipedInFromAFileIsNotOverwritten) {
  for (const std::string target : {"piped.session", "/proc/self/fd/0"}) {
    const fs::path script =
        write("piped.session", "step 2\nrecord " + (target[0] == '/' ? target : (dir_ / target).string()) + "\n");
    const std::string before = slurp(script);
    const Result r = run("session " + (fs::path(DWATCH_SCENARIOS_DIR) / "token_ring.toml").string() + " --script - < " +
                         script.string());
    EXPECT_NE(r.err.find("would overwrite the input /dev/stdin"), std::string::npos) << target << ": " << r.err;
    EXPECT_EQ(slurp(script), before) << target;
  }
}

TEST_F(Cli, BadOptionsAreBadInput) {
  EXPECT_EQ(run("replay x.jsonl -w 'modules(a); (a.x=1)' --algorithm sideways").code, 2);
  EXPECT_EQ(run("replay " + (dir_ / "missing.jsonl").string() + " -w 'modules(a); (a.x=1)'").code, 2);
  const Result unknown = run("frobnicate");
  EXPECT_EQ(unknown.code, 2);
  EXPECT_NE(
      unknown.err.find("unknown command 'frobnicate' (the commands: run, check, replay, render, session, view, bench"),
      std::string::npos)
      << unknown.err;
  const Result version = run("--version");
  EXPECT_EQ(version.code, 0);
  EXPECT_EQ(version.out, "dwatch " DWATCH_VERSION "\n");
  for (const std::string command : {"run ", "render --out x.png ", "replay -w 'modules(a); (a.x=1)' ", "check @"}) {
    const Result folder = run(command + dir_.string());
    EXPECT_EQ(folder.code, 2) << command;
    EXPECT_NE(folder.err.find("Is a directory"), std::string::npos) << command << ": " << folder.err;
  }
  const fs::path c = cases_ / "07_last_last_single";
  const Result unwritable = run("replay " + (c / "trace.jsonl").string() + " -w @" + (c / "watch.txt").string() +
                                " --matches /nonexistent/dir/m.jsonl");
  EXPECT_EQ(unwritable.code, 2);
  EXPECT_NE(unwritable.err.find("--matches: cannot write /nonexistent/dir/m.jsonl: No such file or directory"),
            std::string::npos)
      << unwritable.err;
  EXPECT_EQ(run("").code, 2);
  // A word a command does not take is named as given (CLI11 listed them backwards: "not expected:
  // f --scriptt").
  expect_refused("check --explainn 'modules(a); a.x = 1' f",
                 "dwatch: error: unknown option '--explainn' for 'dwatch check' (dwatch check --help lists what it "
                 "takes)\n");
  const Result extra = run("run a.toml surplus");
  EXPECT_EQ(extra.code, 2);
  EXPECT_NE(extra.err.find("unexpected argument 'surplus' for 'dwatch run'"), std::string::npos) << extra.err;
  // An option given last took the command's own word as its value: the message says which.
  expect_refused("run --record S",
                 "dwatch: error: scenario is required ('--record' took 'S' as its value: give it one of its own, or "
                 "put the option after the command's own words)\n");
  const Result valueless = run("run a.toml --max-live");
  EXPECT_EQ(valueless.code, 2);
  EXPECT_NE(valueless.err.find("dwatch: error: --max-live: 1 required"), std::string::npos) << valueless.err;
  EXPECT_NE(valueless.err.find("takes a value and was given none"), std::string::npos) << valueless.err;
  // CLI11's own checks are said as every mistake is, pointing at the command's --help.
  expect_refused("run a.toml --steps -1",
                 "dwatch: error: --steps: 'steps' must be between 0 and 10000000, not -1 (dwatch run --help lists "
                 "what it takes)\n");
  const Result bench = run("bench nosuch");
  EXPECT_EQ(bench.code, 2);
  EXPECT_EQ(bench.err.rfind("dwatch: error: name: nosuch not in {", 0), 0u) << bench.err;
  EXPECT_NE(bench.err.find("(dwatch bench --help lists what it takes)"), std::string::npos) << bench.err;
  expect_refused("render a.toml --camera-eye 1,2,3,4",
                 "dwatch: error: --camera-eye: At Most 3 required but received 4 (dwatch render --help lists what "
                 "it takes)\n");
  // What a command prints is its answer: printed nowhere, it did not succeed.
  const fs::path err = dir_ / "full_err";
  const int status =
      std::system((std::string(DWATCH_EXE) + " check 'modules(a); a.x = 1' >/dev/full 2>" + err.string()).c_str());
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 1);
  EXPECT_EQ(slurp(err), "dwatch: error: writing standard output failed: No space left on device\n");
  // A watchpoint the user left unnamed is not given a name the user gave another (w2 here).
  const Result named = run("check 'w2=modules(a); a.x = 1' 'modules(a b); a.x = 1'");
  EXPECT_EQ(named.code, 0) << named.err;
  EXPECT_NE(named.out.find("watchpoint w2_ (<watch 2>)"), std::string::npos) << named.out;
  expect_refused("run a.toml --steps 5 --steps 6", "dwatch: error: --steps: given more than once (give it once)\n");
  // An empty value names no file: it was taken as no --matches at all, and nothing was written.
  expect_refused("run a.toml --matches ''", "dwatch: error: --matches: the value is empty\n");
  // A reading the command line made impossible is said as the command line's, at the watchpoint
  // (it was said at the file's `algorithm = ...` line, which the user had not touched).
  const Result reading = run("run " + std::string(DWATCH_SCENARIOS_DIR) + "/leader_election.toml --shape ordered " +
                             "--algorithm distributed");
  EXPECT_EQ(reading.code, 2);
  EXPECT_NE(reading.err.find("leader_election.toml:17:8: error: with --algorithm distributed --shape ordered from the "
                             "command line: shape \"ordered\" needs states = \"simultaneous\""),
            std::string::npos)
      << reading.err;
}

}  // namespace

// --- dwatch run -------------------------------------------------------------------------------

const fs::path kScenarios = DWATCH_SCENARIOS_DIR;

std::string line_with(const std::string& text, const std::string& what) {
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.find(what) != std::string::npos) return line;
  return "";
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

TEST_F(Cli, RenderWritesTheViewAndNamesTheHighlightedGroup) {
  const fs::path png = dir_ / "ring.png";
  const Result r = run("render " + (kScenarios / "token_ring.toml").string() +
                       " --step 41 --width 320 --height 200 --out " + png.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(png_size(png), std::make_pair(320u, 200u));
  EXPECT_NE(r.out.find("1 group highlighted"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("token_from_nowhere t=41: a=7 x=8 b=9"), std::string::npos) << r.out;
}

// OSMesa (LLVM with it, some 45 MiB) is opened only by what draws headless, and libav* (some 22
// MiB more) only by what writes a video: a run that writes neither loads neither. What the
// dynamic loader reports (LD_DEBUG) tells.
TEST_F(Cli, OnlyWhatDrawsLoadsOsMesaAndOnlyVideosLoadLibav) {
  struct Loaded {
    bool osmesa = false, libav = false;
  };
  const auto loaded = [&](const std::string& args) {
    const Result r = run_with_env("LD_DEBUG=files", args);
    EXPECT_EQ(r.code, 0) << args << "\n" << r.out;
    return Loaded{r.err.find("libOSMesa") != std::string::npos, r.err.find("libavcodec") != std::string::npos};
  };
  const std::string scenario = (kScenarios / "token_ring.toml").string();
  const Loaded run = loaded("run " + scenario + " --steps 5 --no-progress");
  EXPECT_FALSE(run.osmesa);
  EXPECT_FALSE(run.libav);
  EXPECT_FALSE(loaded("check 'modules(a); (a.x = 1)'").osmesa);
  const Loaded picture =
      loaded("render " + scenario + " --step 3 --width 64 --height 48 --out " + (dir_ / "r.png").string());
  EXPECT_TRUE(picture.osmesa);
  EXPECT_FALSE(picture.libav);
  EXPECT_EQ(png_size(dir_ / "r.png"), std::make_pair(64u, 48u));
  const Loaded video =
      loaded("render " + scenario + " --from 0 --to 3 --width 64 --height 48 --video " + (dir_ / "r.webm").string());
  EXPECT_TRUE(video.osmesa);
  EXPECT_TRUE(video.libav);
  EXPECT_GT(fs::file_size(dir_ / "r.webm"), 0u);
}

TEST_F(Cli, RenderHighlightsTheFirstAllOrNoneOfTheGroupsAtTheStep) {
  const std::string le = (kScenarios / "leader_election.toml").string() + " --step 1 --width 64 --height 48 --out " +
                         (dir_ / "le.png").string();
  // `dwatch run` reports 91 matches at step 1 of this scenario.
  EXPECT_NE(run("render " + le).out.find("1 group highlighted"), std::string::npos);
  EXPECT_NE(run("render " + le + " --highlight all").out.find("91 groups highlighted"), std::string::npos);
  EXPECT_NE(run("render " + le + " --highlight none").out.find("0 groups highlighted"), std::string::npos);
}

TEST_F(Cli, RunRenderDrawsThePausedStepAsRenderDoes) {
  const std::string scenario = (kScenarios / "token_ring.toml").string();
  const Result ran = run("run " + scenario + " --render " + (dir_ / "run.png").string());
  ASSERT_EQ(ran.code, 0) << ran.err;
  EXPECT_NE(ran.out.find("view of step 41 written to"), std::string::npos) << ran.out;
  ASSERT_EQ(run("render " + scenario + " --step 41 --out " + (dir_ / "render.png").string()).code, 0);
  EXPECT_EQ(slurp(dir_ / "run.png"), slurp(dir_ / "render.png"));
  // Without a pause, the last step.
  const Result last = run("run " + (kScenarios / "token_ring_correct.toml").string() + " --steps 30 --render " +
                          (dir_ / "last.png").string());
  ASSERT_EQ(last.code, 0) << last.err;
  EXPECT_NE(last.out.find("view of step 29 written to"), std::string::npos) << last.out;
}

TEST_F(Cli, InputsWithoutEndAreRefusedAtTheirLimit) {
  // Each would grow to gigabytes if read whole.
  const std::string scenario = (dir_ / "z.toml").string();
  std::ofstream(scenario) << "[lattice]\nkind = \"line\"\nsize = [3]\n[[program]]\nscript = \"/dev/zero\"\n";
  for (const std::string& command :
       std::vector<std::string>{"check @/dev/zero", "run /dev/zero", "run " + scenario,
                                "session " + (kScenarios / "token_ring.toml").string() + " --script /dev/zero",
                                "replay /dev/zero --watch 'modules(a);a.token=1'"}) {
    const Result r = run(command);
    EXPECT_EQ(r.code, 2) << command;
    EXPECT_NE(r.err.find("a NUL byte at line 1, column 1: it is not a text file"), std::string::npos)
        << command << ": " << r.err;
  }
  const Result endless = run("session " + (kScenarios / "token_ring.toml").string() + " --script - < /dev/urandom");
  EXPECT_EQ(endless.code, 2);
  EXPECT_NE(endless.err.find("cannot read standard input: "), std::string::npos) << endless.err;
}

TEST_F(Cli, RenderMistakesAreBadInput) {
  const std::string scenario = (kScenarios / "token_ring.toml").string();
  const Result var = run("render " + scenario + " --color-by nope --out " + (dir_ / "x.png").string());
  EXPECT_EQ(var.code, 2);
  EXPECT_NE(var.err.find("no program has a variable named \"nope\" (there are: token"), std::string::npos) << var.err;
  EXPECT_EQ(run("render " + scenario + " --out /nonexistent/dir/x.png").code, 2);
  EXPECT_EQ(run("render " + scenario + " --out " + (dir_ / "x.png").string() + " --highlight some").code, 2);
  EXPECT_EQ(run("render " + scenario + " --out " + (dir_ / "x.png").string() + " --width 0").code, 2);
  EXPECT_EQ(run("render " + (dir_ / "missing.toml").string() + " --out " + (dir_ / "x.png").string()).code, 2);
  EXPECT_EQ(run("run " + scenario + " --render /nonexistent/dir/x.png").code, 2);
  // A camera that could only draw a blank picture is refused.
  for (const std::string camera :
       {"--camera-eye 1,2,3 --camera-target 1,2,3", "--camera-eye 5,5,0 --camera-target 5,5.000001,0",
        "--camera-eye nan,0,5", "--camera-eye 0,inf,5", "--camera-eye 1e300,0,0", "--camera-target 0,0,-1e7"}) {
    const Result r = run("render " + scenario + " --out " + (dir_ / "x.png").string() + " " + camera);
    EXPECT_EQ(r.code, 2) << camera;
    EXPECT_NE(r.err.find("error: "), std::string::npos) << camera << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(dir_ / "x.png"));
  // So is one that sees none of the ensemble once it is run: looking away, or from too far.
  // A target alone too, with the eye fitted from it, on the command line or in [view].
  for (const std::string camera : {"--camera-eye 6,4,30 --camera-target 6,4,100", "--camera-eye 0,0,900000",
                                   "--camera-target 1e6,1e6,1e6", "--camera-target 0,0,-1000"}) {
    const Result r = run("render " + scenario + " --out " + (dir_ / "x.png").string() + " " + camera);
    EXPECT_EQ(r.code, 2) << camera;
    EXPECT_NE(r.err.find("error: the camera at "), std::string::npos) << camera << ": " << r.err;
  }
  const std::string targeted = write("far.toml", slurp(scenario) + "camera_target = [1e6, 1e6, 1e6]\n").string();
  for (const std::string& command : {"render " + targeted + " --out " + (dir_ / "x.png").string(),
                                     "run " + targeted + " --render " + (dir_ / "x.png").string()}) {
    const Result r = run(command);
    EXPECT_EQ(r.code, 2) << command;
    EXPECT_NE(r.err.find("error: the camera at "), std::string::npos) << command << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(dir_ / "x.png"));
}

// --- dwatch render --video ----------------------------------------------------------------------

// The camera a video was drawn with, from its summary, as render's options.
std::string video_camera(const std::string& out) {
  const size_t at = out.find("  camera: ");
  if (at == std::string::npos) return "";
  return out.substr(at + 10, out.find('\n', at) - at - 10);
}

// Each frame is the step as `render --step T` draws it with the video's camera, which is fitted
// to the first frame; a step with a matched group shows its red outline and links.
TEST_F(Cli, RenderVideoDrawsEachStepAsRenderDoes) {
  namespace video = dw::render::test;
  const std::string scenario = (kScenarios / "token_ring.toml").string();
  const std::string size = " --width 640 --height 360";
  const fs::path first = dir_ / "39.png";
  ASSERT_EQ(run("render " + scenario + " --step 39 --out " + first.string() + size).code, 0);
  for (const auto& [name, codec] : {std::pair{"ring.mp4", "h264"}, {"ring.webm", "vp9"}}) {
    SCOPED_TRACE(name);
    const fs::path file = dir_ / name;
    const Result r = run("render " + scenario + " --video " + file.string() + " --from 39 --to 43" + size);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("steps 39..43, 5 frames at 10 frames/s"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("1 step with a group highlighted"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("first: token_from_nowhere t=41: a=7 x=8 b=9"), std::string::npos) << r.out;
    const video::DecodedVideo v = video::decode_video(file.string());
    ASSERT_EQ(v.error, "");
    EXPECT_EQ(v.codec, codec);
    EXPECT_EQ(v.width, 640);
    EXPECT_EQ(v.height, 360);
    EXPECT_NEAR(v.fps, 10, 0.01);
    ASSERT_EQ(v.frames.size(), 5u);
    // The first frame: step 39 with the fitted camera, as `render --step 39` draws it.
    const auto png = dw::render::read_png(first.string());
    ASSERT_TRUE(png);
    EXPECT_LT(video::mean_absolute_difference(v.frames[0], *png), 4.0);  // another step: 18
    // Step 41 (frame 2), drawn by `render --step 41` with the video's camera.
    const std::string camera = video_camera(r.out);
    ASSERT_NE(camera.find("--camera-eye "), std::string::npos) << r.out;
    const fs::path step41 = dir_ / "41.png";
    ASSERT_EQ(run("render " + scenario + " --step 41 --out " + step41.string() + size + " " + camera).code, 0);
    const auto highlighted = dw::render::read_png(step41.string());
    ASSERT_TRUE(highlighted);
    EXPECT_LT(video::mean_absolute_difference(v.frames[2], *highlighted), 4.0);
    EXPECT_GT(video::mean_absolute_difference(v.frames[1], *highlighted), 10.0) << "frame 1 is another step";
    const int64_t red = video::count_pixels(*highlighted, video::group_red);
    ASSERT_GT(red, 1000);
    EXPECT_GT(video::count_pixels(v.frames[2], video::group_red), red * 3 / 4);
    for (const size_t plain : {0u, 1u, 3u, 4u})
      EXPECT_LT(video::count_pixels(v.frames[plain], video::group_red), red / 20);
  }
  // --fps, and the whole scenario by default.
  const Result all =
      run("render " + scenario + " --video " + (dir_ / "all.mp4").string() + " --fps 25 --width 160 --height 96");
  ASSERT_EQ(all.code, 0) << all.err;
  const video::DecodedVideo whole = video::decode_video((dir_ / "all.mp4").string());
  EXPECT_EQ(whole.frames.size(), 100u) << "token_ring has 100 steps";
  EXPECT_NEAR(whole.fps, 25, 0.01);
}

TEST_F(Cli, RenderVideoMistakesAreBadInputAndWriteNothing) {
  const std::string scenario = (kScenarios / "token_ring.toml").string();
  const std::string video = " --video " + (dir_ / "v.mp4").string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {video + " --out " + (dir_ / "x.png").string(), "error: --out and --video are exclusive"},
      {"", "error: render needs --out PNG (one step) or --video FILE.mp4|FILE.webm"},
      {" --video " + (dir_ / "v.avi").string(), "error: --video: " + (dir_ / "v.avi").string() +
                                                    ": a video's name ends in .mp4 (H.264) or .webm (VP9), not '.avi'"},
      {" --video /nonexistent/dir/v.mp4",
       "error: --video: cannot write /nonexistent/dir/v.mp4: No such file or directory"},
      {video + " --width 321", "error: --width 321: a video's width and height must be even"},
      {video + " --height 199", "error: --height 199: a video's width and height must be even"},
      {video + " --step 3", "error: --step is for --out"},
      {video + " --from 9 --to 3", "error: --from 9 is after --to 3"},
      {video + " --from 150", "error: --from 150 is after the last step, 99 (--to)"},
      {" --out " + (dir_ / "x.png").string() + " --from 3", "error: --from, --to and --fps are for --video"},
      {video + " --fps 0", "'fps' must be between 1 and 240, not 0"},
      {" --video - ", "error: --video needs a file name"},
      {" --video " + scenario, "would overwrite the input"},
  };
  for (const auto& [options, message] : cases) {
    const Result r = run("render " + scenario + options);
    EXPECT_EQ(r.code, 2) << options;
    EXPECT_NE(r.err.find(message), std::string::npos) << options << ": " << r.err;
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 2) << "only stdout and stderr";
}

// A write that fails is exit 1 naming the path and the reason, and leaves no file.
TEST_F(Cli, RenderVideoThatCannotBeWrittenNamesTheReason) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  fs::create_symlink("/dev/full", dir_ / "full.webm");
  const Result r = run("render " + (kScenarios / "token_ring.toml").string() + " --video " +
                       (dir_ / "full.webm").string() + " --to 3 --width 64 --height 48");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("writing " + (dir_ / "full.webm").string() + " failed: No space left on device"),
            std::string::npos)
      << r.err;
}

namespace {

// Every number on the command line takes its TOML key's range and words; none wraps.
TEST_F(Cli, CommandLineNumbersTakeTheRangesOfTheirKeys) {
  const std::string scenario = (kScenarios / "token_ring.toml").string();
  for (const std::string value : {"-1", "18446744073709551615", "1000001", "0", "1e3", "x"}) {
    const Result r = run("run " + scenario + " --history-mb " + value);
    EXPECT_EQ(r.code, 2) << value << ": " << r.err;
    const std::string expected = value == "1e3" || value == "x"
                                     ? "'history_mb' must be an integer, not '" + value + "'"
                                     : "'history_mb' must be between 1 and 1000000, not " + value;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
  }
  // The same words as the scenario key.
  const fs::path bad = write(
      "bad.toml", "history_mb = -1\n[lattice]\nkind = \"ring\"\nsize = [5]\n[[program]]\nname = \"token_ring\"\n");
  EXPECT_NE(run("run " + bad.string()).err.find("'history_mb' must be between 1 and 1000000, not -1"),
            std::string::npos);
  for (const std::string option : {"--seed -1", "--steps -5", "--threads 0", "--threads 4294967297", "--print -1"})
    EXPECT_EQ(run("run " + scenario + " " + option).code, 2) << option;
  EXPECT_EQ(run("render " + scenario + " --out " + (dir_ / "x.png").string() + " --width -1").code, 2);
  EXPECT_EQ(run("replay x.jsonl -w 'modules(a); (a.x=1)' --max-live -1").code, 2);
  for (const char* gib : {"nan", "inf", "-1", "0"})
    EXPECT_EQ(run(std::string("replay x.jsonl -w 'modules(a); (a.x=1)' --max-frame-memory ") + gib).code, 2) << gib;
  EXPECT_EQ(run("bench engine --repeat 0").code, 2);
  EXPECT_EQ(run("replay x.jsonl -w 'modules(a); (a.x=1)' --max-module-steps 0").code, 2);
  // Two lines ten million steps apart: refused at once with the budget, not detected for minutes.
  const fs::path gap = write("gap.jsonl",
                             "{\"t\":0,\"m\":0,\"vars\":{\"x\":1},\"nbrs\":[1,2,3,4,5,6,7,8,9,10,"
                             "11,12,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28,29,30,31,32,33,34,35,36,"
                             "37,38,39,40,41,42,43,44,45,46,47,48,49,50,51,52,53,54,55,56,57,58,59,60,61,62,"
                             "63,64,65,66,67,68,69,70,71,72,73,74,75,76,77,78,79,80,81,82,83,84,85,86,87,88,"
                             "89,90,91,92,93,94,95,96,97,98,99,100]}\n"
                             "{\"t\":9999999,\"m\":0,\"vars\":{},\"nbrs\":[]}\n");
  const Result refused = run("replay " + gap.string() + " -w 'modules(a); (a.x=1)'");
  EXPECT_EQ(refused.code, 2);
  EXPECT_NE(refused.err.find("its 10000000 steps of 101 modules"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("--max-module-steps sets the limit"), std::string::npos) << refused.err;
}

// Two outputs on one file, or an output on an input, in any spelling: bad input before any run.
TEST_F(Cli, OutputsThatWouldClobberEachOtherOrAnInputAreBadInput) {
  const fs::path scenario = dir_ / "s.toml";
  fs::copy_file(kScenarios / "token_ring.toml", scenario);
  const std::string original = slurp(scenario);
  const std::string run_it = "run " + scenario.string() + " --no-progress";
  const fs::path x = dir_ / "x.jsonl";
  fs::create_symlink(x, dir_ / "link.jsonl");
  for (const std::string& outputs : std::vector<std::string>{
           "--matches " + x.string() + " --record " + x.string(), "--matches " + x.string() + " --stats " + x.string(),
           "--matches " + x.string() + " --stats " + (dir_ / "." / "x.jsonl").string(),
           "--matches " + x.string() + " --record " + (dir_ / "link.jsonl").string(), "--stats " + scenario.string(),
           "--render " + scenario.string(), "--matches - --stats /dev/stdout"}) {
    const Result r = run(run_it + " " + outputs);
    EXPECT_EQ(r.code, 2) << outputs << "\n" << r.err;
    EXPECT_TRUE(r.err.find("name one file") != std::string::npos ||
                r.err.find("would overwrite the input") != std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(x)) << "nothing ran: " << outputs;
  }
  EXPECT_EQ(slurp(scenario), original);
  // A trace given to replay, and the watch file beside it.
  ASSERT_EQ(run(run_it + " --record " + x.string()).code, 0);
  const std::string trace = slurp(x);
  const fs::path watch = write("w.watch", "modules(a b); (a.token = 1) and (b.token = 1)");
  const Result r1 = run("replay " + x.string() + " -w @" + watch.string() + " --matches " + x.string());
  EXPECT_EQ(r1.code, 2) << r1.err;
  const Result r2 = run("replay " + x.string() + " -w @" + watch.string() + " --stats " + watch.string());
  EXPECT_EQ(r2.code, 2) << r2.err;
  EXPECT_EQ(slurp(x), trace);
  // /dev/null takes any number of outputs.
  EXPECT_EQ(run(run_it + " --matches /dev/null --stats /dev/null").code, 0);
}

// A write that fails is exit 1 naming the path and the reason, and destroys nothing.
TEST_F(Cli, AFailedWriteNamesThePathAndDestroysNothing) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const std::string scenario = (kScenarios / "token_ring.toml").string();
  const Result png = run("render " + scenario + " --step 5 --out /dev/full");
  EXPECT_EQ(png.code, 1) << png.err;
  EXPECT_NE(png.err.find("writing /dev/full failed: No space left on device"), std::string::npos) << png.err;
  EXPECT_TRUE(fs::is_character_file("/dev/full")) << "the device node must survive";
  const Result matches = run("run " + scenario + " --no-progress --matches /dev/full");
  EXPECT_EQ(matches.code, 1) << matches.err;
  EXPECT_TRUE(fs::is_character_file("/dev/full"));
  // A regular file that cannot grow (a file-size limit, SIGXFSZ ignored) keeps its old contents.
  const fs::path old = write("old.png", "old picture");
  const std::string limited = "sh -c 'trap \"\" XFSZ; ulimit -f 2; exec " + std::string(DWATCH_EXE) + " render " +
                              scenario + " --step 5 --out " + old.string() + "'";
  const int status = std::system((limited + " >/dev/null 2>&1").c_str());
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 1);
  EXPECT_EQ(slurp(old), "old picture");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 3) << "no temporary left behind";
}

// Summaries count what is there: present modules, not lattice cells; no empty lists.
TEST_F(Cli, SummariesSayWhatIsThere) {
  const Result slide = run("run " + (kScenarios / "slide.toml").string() + " --no-progress --steps 10");
  EXPECT_NE(slide.out.find(": 16 modules (cubic 12x1x2, 8 cells left empty)"), std::string::npos) << slide.out;
  const Result none = run("run " + (kScenarios / "token_ring.toml").string() + " --no-progress --steps 0");
  EXPECT_EQ(none.code, 0) << none.err;
  EXPECT_EQ(none.out.find("by slots filled"), std::string::npos) << none.out;
  const fs::path counted = write("count.toml",
                                 "[lattice]\nkind = \"ring\"\nsize = [8]\n[[program]]\nname = \"token_ring\"\n"
                                 "[[watch]]\nname = \"tokens\"\ntext = \"modules(a); (a.token = 1)\"\n"
                                 "action = \"count\"\n");
  const Result render = run("render " + counted.string() + " --step 3 --out " + (dir_ / "c.png").string());
  EXPECT_EQ(render.code, 0) << render.err;
  EXPECT_NE(render.out.find("tokens only counts its matches (action = \"count\")"), std::string::npos) << render.out;
  // What a count watchpoint counted is in the match log, never a 0: one token per step, 20 steps.
  const Result ran =
      run("run " + counted.string() + " --no-progress --steps 20 --matches " + (dir_ / "c.jsonl").string());
  EXPECT_NE(ran.out.find("tokens [distributed, count]: 20 matches"), std::string::npos) << ran.out;
  EXPECT_EQ(slurp(dir_ / "c.jsonl"), "{\"watch\":\"tokens\",\"counted\":20}\n");
  const fs::path trace = write("t.jsonl", "{\"t\":0,\"m\":0,\"vars\":{\"x\":1},\"nbrs\":[1,2]}\n");
  const Result replay = run("replay " + trace.string() + " -w 'modules(a); (a.x = 1)'");
  EXPECT_NE(replay.out.find("1 lines, 1 steps, 1 modules (and 2 named only as neighbours)"), std::string::npos)
      << replay.out;
}

}  // namespace

namespace {

class ShapesCli : public Cli {};

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

TEST_F(ShapesCli, CheckStatesEachReadingsLag) {
  const Result r = run("check 'modules(a b c d); (a.x = 1) and (b.next.x = 0)'");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("lag E+ = 1"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("lag E+ + k - 1 = 4"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("L = k - 1 = 3 hops for chain, k(k - 1)/2 = 6 for ordered and any; lag E+ + L = 4 / 7"),
            std::string::npos)
      << r.out;
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
