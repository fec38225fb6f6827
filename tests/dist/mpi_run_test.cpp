// `mpirun -np N dwatch run` (dist/, docs/design.md §12) as a user runs it: every output file and the state
// hash equal those of the same run in one process, for 2, 3 and 4 ranks, on static lattices and
// on a lattice that moves (the Bullet world, kept whole on every rank, its islands stepped in
// runs by the ranks).
#include <nlohmann/json.hpp>

#include "tests/app/cli.h"

namespace dw::cli_test {
namespace {

class MpiRun : public Cli {
 protected:
  void SetUp() override {
    Cli::SetUp();
    // Open MPI refuses root without these (docs/design.md §12); the tests may run as root in CI.
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    // Under the sanitizers (scripts/test.sh --asan): Open MPI's plugins stay loaded to the end and
    // their stacks are walked slowly but whole, so that LeakSanitizer can name them (and
    // tests/lsan.supp suppress what Open MPI leaves behind).
    ::setenv("OMPI_MCA_mca_base_component_disable_dlclose", "1", 1);
    ::setenv("PMIX_MCA_mca_base_component_disable_dlclose", "1", 1);
    if (const char* asan = std::getenv("ASAN_OPTIONS"))
      ::setenv("ASAN_OPTIONS", (std::string(asan) + ":fast_unwind_on_malloc=0").c_str(), 1);
  }

  // dwatch over `ranks` processes, started as a user starts it.
  Result mpirun(int ranks, const std::string& args) {
    const fs::path out = dir_ / "stdout", err = dir_ / "stderr";
    const std::string cmd = std::string(DWATCH_MPIRUN) + " --oversubscribe -np " + std::to_string(ranks) + " " +
                            DWATCH_EXE + " " + args + " >" + out.string() + " 2>" + err.string();
    const int status = std::system(cmd.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
  }

  // The run's statistics but for what depends on how it ran (time, threads, ranks).
  static nlohmann::json results(const fs::path& stats) {
    nlohmann::json j = nlohmann::json::parse(slurp(stats));
    for (const char* key : {"seconds", "setup_seconds", "threads", "ranks", "partition", "bytes_between_ranks",
                            "peak_mib", "peak_mib_all_ranks", "physics_seconds"})
      j.erase(key);
    for (nlohmann::json& w : j["watches"]) {  // a detector's time (a zero-slot watchpoint's)
      w.erase("seconds");
      for (nlohmann::json& step : w["per_step"]) step.erase("seconds");
    }
    return j;
  }

  // Whether the run's programs or agents sent anything.
  static bool sends(const nlohmann::json& stats) {
    uint64_t sent = stats["program_messages"].get<uint64_t>();
    for (const nlohmann::json& w : stats["watches"]) sent += w["messages"].get<uint64_t>();
    return sent > 0;
  }

  // Runs `args` in one process and over 2, 3 and 4 ranks (with `threads` each, and `over_ranks`),
  // and expects the same files: matches, statistics (with the state hash) and, if `record`, the trace.
  void expect_same_over_ranks(const std::string& args, int threads = 1, bool record = false,
                              const std::string& over_ranks = "") {
    auto outputs = [&](const std::string& tag) {
      return " --matches " + (dir_ / (tag + ".jsonl")).string() + " --stats " + (dir_ / (tag + ".json")).string() +
             (record ? " --record " + (dir_ / (tag + ".trace")).string() : "");
    };
    const Result one = run("run " + args + " -j " + std::to_string(threads) + outputs("one"));
    ASSERT_EQ(one.code, 0) << one.err;
    const nlohmann::json expected = results(dir_ / "one.json");
    ASSERT_GT(expected["steps"].get<int>(), 0);
    for (int ranks : {2, 3, 4}) {
      SCOPED_TRACE(std::to_string(ranks) + " ranks");
      const std::string tag = "r" + std::to_string(ranks);
      const Result r =
          mpirun(ranks, "run " + args + " " + over_ranks + " -j " + std::to_string(threads) + outputs(tag));
      ASSERT_EQ(r.code, 0) << r.err;
      EXPECT_EQ(slurp(dir_ / (tag + ".jsonl")), slurp(dir_ / "one.jsonl"));
      EXPECT_EQ(results(dir_ / (tag + ".json")), expected);
      const nlohmann::json how = nlohmann::json::parse(slurp(dir_ / (tag + ".json")));
      EXPECT_EQ(how["ranks"], ranks);
      // Slabs always border, where modules or agents send (METIS may keep a small graph's links in
      // one part; a one-slot watchpoint sends nothing, and what `all` reads is gathered, not sent).
      if (how["partition"] == "blocks" && sends(expected)) {
        EXPECT_GT(how["bytes_between_ranks"].get<uint64_t>(), 0u) << "the parts did talk";
      }
      if (record) {
        EXPECT_EQ(slurp(dir_ / (tag + ".trace")), slurp(dir_ / "one.trace"));
      }
      // Rank 0 alone speaks: one summary, the same hash as the one process printed.
      const std::string hash = "state hash: " + expected["state_hash"].get<std::string>();
      EXPECT_EQ(r.out.find(hash), r.out.rfind(hash)) << r.out;
      EXPECT_NE(r.out.find(hash), std::string::npos) << r.out;
    }
  }

  const std::string scenarios_ = DWATCH_SCENARIOS_DIR;
};

TEST_F(MpiRun, LeaderElectionOnAHexSheetEqualsOneProcess) {
  expect_same_over_ranks(scenarios_ + "/leader_election.toml --algorithm distributed");
  // The run found something to compare: the 1-hop bug's leaders.
  EXPECT_GT(results(dir_ / "one.json")["matches"].get<int>(), 0);
}

TEST_F(MpiRun, ScheduledInterventionsEqualOneProcess) {
  // The leader election logging every match, with a module removed and a variable set on the way:
  // interventions apply on every rank, to the world whole and to the owner's variables.
  std::string text = slurp(scenarios_ + "/leader_election.toml");
  text.replace(text.find("action = \"pause\""), 16, "action = \"log\"");
  const fs::path scenario = write("events.toml", text +
                                                     "\n[[event]]\nat = 4\nmodule = 70\nremove = true\n"
                                                     "\n[[event]]\nat = 3\nmodule = 90\nset = { isLeader = 1 }\n");
  expect_same_over_ranks(scenario.string() + " --algorithm distributed");
  EXPECT_GT(results(dir_ / "one.json")["matches"].get<int>(), 1000);
}

TEST_F(MpiRun, TableOneCubeEqualsOneProcessWithTwoThreadsPerRank) {
  expect_same_over_ranks(scenarios_ + "/table1.toml --steps 30", 2);
  EXPECT_GT(results(dir_ / "one.json")["matches"].get<int>(), 1000);
  EXPECT_EQ(nlohmann::json::parse(slurp(dir_ / "r3.json"))["partition"], "blocks") << "a static lattice's default";
}

TEST_F(MpiRun, TableOneCubeByAMetisPartitionEqualsOneProcess) {
  expect_same_over_ranks(scenarios_ + "/table1.toml --steps 20", 1, false, "--partition metis");
  EXPECT_EQ(nlohmann::json::parse(slurp(dir_ / "r3.json"))["partition"], "metis");
}

TEST_F(MpiRun, TokenRingPausedAndRolledBackEqualsOneProcess) {
  // A pause found k - 1 steps late rolls every rank back to the match's step.
  expect_same_over_ranks(scenarios_ + "/token_ring_distributed.toml --states consistent");
  EXPECT_TRUE(results(dir_ / "one.json").contains("pause"));
}

TEST_F(MpiRun, SlidingModulesInTheBulletWorldEqualOneProcessTraceIncluded) {
  // Contacts made and broken as modules glide: N(m, t) changes, from actuations on every rank.
  expect_same_over_ranks(scenarios_ + "/slide.toml --algorithm distributed", 1, true);
  EXPECT_EQ(nlohmann::json::parse(slurp(dir_ / "r3.json"))["partition"], "metis") << "the default when bodies move";
  expect_same_over_ranks(scenarios_ + "/slide.toml --algorithm distributed", 1, true, "--partition blocks");
  EXPECT_EQ(nlohmann::json::parse(slurp(dir_ / "r3.json"))["partition"], "blocks");
  EXPECT_GT(results(dir_ / "one.json")["matches"].get<int>(), 0);
}

TEST_F(MpiRun, AWallStruckAndTornEqualsOneProcessTraceIncluded) {
  // The ball and the modules it tears off are islands that the ranks step in runs, each rank
  // taking the others' results: a trace, matches and hash as in one process.
  expect_same_over_ranks(scenarios_ + "/push_wall.toml --algorithm distributed", 1, true);
  EXPECT_GT(results(dir_ / "one.json")["watches"][0]["matches"].get<int>(), 0) << "modules were torn off";
}

TEST_F(MpiRun, ManyBodiesMovingAtOnceEqualOneProcessTraceIncluded) {
  // Four balls through sixteen towers: hundreds of bodies in islands that meet and part, each
  // stepped by the rank whose run it falls in that step, spanning the ranks' modules.
  expect_same_over_ranks(scenarios_ + "/demolition.toml --steps 250", 1, true);
  EXPECT_GT(results(dir_ / "one.json")["watches"][0]["matches"].get<int>(), 50) << "towers were torn";
}

TEST_F(MpiRun, NeighbourAggregatesOverMovingBodiesEqualOneProcess) {
  // A rank holds the neighbour lists of its window only (docs/design.md §12a): its own modules' and
  // those of the modules within reach of them, which an aggregate over a neighbour's neighbours and
  // a pair of neighbouring slots read while the towers fall across the ranks' parts.
  std::string text = slurp(scenarios_ + "/demolition.toml");
  text +=
      "[[watch]]\nname = \"crowded\"\naction = \"log\"\n"
      "text = \"modules(a b); count(n in neighbors(a): n.nbrs >= 4) >= 2 and "
      "sum(n in neighbors(b.last): n.nbrs) > b.nbrs + 6\"\n"
      "[[watch]]\nname = \"cornered\"\naction = \"log\"\n"
      "text = \"modules(a b); count(n in neighbors(a): neighbor(n b) and n.nbrs >= 3) >= 1 and "
      "(b.nbrs <= 3)\"\n";
  const fs::path scenario = write("demolition_crowded.toml", text);
  expect_same_over_ranks(scenario.string() + " --steps 150 --algorithm distributed", 1, true);
  const nlohmann::json one = results(dir_ / "one.json");
  EXPECT_GT(one["watches"][2]["matches"].get<int>(), 20);
  EXPECT_GT(one["watches"][3]["matches"].get<int>(), 20);
}

TEST_F(MpiRun, WiderDomainsAndZeroSlotWatchpointsOverMovingBodiesEqualOneProcess) {
  // docs/design.md §4c over ranks: within() and component() read the lists of modules past a rank's
  // window, all and component() every rank's values of the step itself, and a zero-slot
  // watchpoint the whole ensemble; the towers fall across the ranks' parts.
  std::string text = slurp(scenarios_ + "/demolition.toml");
  text +=
      "[[watch]]\nname = \"far\"\naction = \"log\"\n"
      "text = \"modules(a); a.moving = 1 and count(n in within(a, 3): n.nbrs >= 3) >= 6\"\n"
      "[[watch]]\nname = \"cluster\"\naction = \"log\"\n"
      "text = \"modules(a); a.moving = 1 and count(n in component(a: n.moving = 1): n.nbrs >= 3) >= 4\"\n"
      "[[watch]]\nname = \"crowd\"\naction = \"log\"\n"
      "text = \"modules(a b); a.moving = 1 and b.nbrs >= 2 and count(n in all: n.moving = 1) > 20\"\n"
      "[[watch]]\nname = \"many_moving\"\naction = \"log\"\n"
      "text = \"modules(); count(n in all: n.moving = 1) > 30\"\n";
  const fs::path scenario = write("demolition_wider.toml", text);
  expect_same_over_ranks(scenario.string() + " --steps 100 --algorithm distributed", 1, false);
  const nlohmann::json one = results(dir_ / "one.json");
  for (int w = 2; w < 6; ++w) EXPECT_GT(one["watches"][w]["matches"].get<int>(), 20) << w;
}

TEST_F(MpiRun, TheScenariosOfTheLanguagesWiderFormsEqualOneProcess) {
  // docs/design.md §4c as users write it: argmin in an action, component(), a zero-slot
  // watchpoint over all, and windows in time (times, since), read distributed.
  for (const char* name : {"bfs_tree_ldp.toml", "cluster_heads.toml", "one_token_ring.toml", "parent_flap.toml",
                           "leader_since_won.toml"}) {
    SCOPED_TRACE(name);
    expect_same_over_ranks(scenarios_ + "/" + name + " --algorithm distributed --states consistent");
    EXPECT_GT(results(dir_ / "one.json")["matches"].get<int>(), 0);
  }
  EXPECT_GT(nlohmann::json::parse(slurp(dir_ / "one.json"))["watches"][0]["matches"].get<int>(), 0);
}

TEST_F(MpiRun, EveryOtherPhysicsScenarioEqualsOneProcess) {
  // Read as ranks can read them: distributed, over consistent states.
  for (const char* name : {"smart_blocks_flow.toml", "catoms3d_roll.toml", "token_ring_physics.toml",
                           "leader_election_physics.toml", "catoms3d_leader_election.toml"}) {
    SCOPED_TRACE(name);
    expect_same_over_ranks(scenarios_ + "/" + name + " --algorithm distributed --states consistent");
  }
}

// The plausibility scenes (scenarios/physics/, docs/design.md §8a): free boxes stacked on each
// other and the ground (the contact cache that warm-starts them is part of the state), two boxes
// resting apart (two islands, which different ranks step), a box launched by a scheduled push, a
// heavy prop on a light cube. (The pile, 1,000 such boxes in one island, is the column's case.)
TEST_F(MpiRun, ThePlausibilityScenesEqualOneProcess) {
  for (const char* scene : {"column.toml --steps 200", "resting_boxes.toml --steps 150",
                            "launched_box.toml --steps 100", "heavy_on_light.toml --steps 150"}) {
    SCOPED_TRACE(scene);
    expect_same_over_ranks(scenarios_ + "/physics/" + scene);
  }
}

// The paper's own modules (docs/physics.md): 2-D catoms climbing a pyramid in a vertical plane and
// Hexanodes walking round a patch (pivots glided by every rank alike, a Lua program), read as ranks
// can read them, and the pile of free discs that rolling resistance brings to rest (islands that
// roll apart, stepped by different ranks). The same matches, trace and hashes as one process; the
// watchpoints find what they find in one process: the climbers on the top row from step 53, the
// walkers meeting at step 58.
TEST_F(MpiRun, ThePapersOwnModulesEqualOneProcess) {
  const std::string reading = " --algorithm distributed --states consistent";
  expect_same_over_ranks(scenarios_ + "/catoms2d_climb.toml" + reading, 1, true);
  std::string matches = slurp(dir_ / "one.jsonl");
  EXPECT_EQ(matches.substr(0, matches.find('\n')), R"({"watch":"climber_on_top","t":53,"slots":{"a":0}})");
  EXPECT_EQ(results(dir_ / "one.json")["matches"].get<int>(), 54);
  expect_same_over_ranks(scenarios_ + "/hexanodes_walk.toml" + reading, 1, true);
  matches = slurp(dir_ / "one.jsonl");
  EXPECT_EQ(matches.substr(0, matches.find('\n')), R"({"watch":"walkers_meet","t":58,"slots":{"a":25,"b":30}})");
  EXPECT_EQ(results(dir_ / "one.json")["matches"].get<int>(), 282);  // both orders, steps 58 to 198
  expect_same_over_ranks(scenarios_ + "/physics/disc_pyramid.toml --steps 450", 1, true);
}

TEST_F(MpiRun, WatchpointActionsEqualOneProcess) {
  // LDP's gradient read by the agents (docs/design.md §4b): the actions' values are gathered with the
  // matches, and each rank sets its own modules' variables, at the same step as one process.
  std::string text = slurp(scenarios_ + "/gradient_ldp.toml");
  const std::string script = "script = \"lua/";
  text.replace(text.find(script), script.size(), "script = \"" + scenarios_ + "/lua/");
  text.replace(text.find("action = \"count\""), 16, "action = \"log\"");
  const fs::path scenario = write("gradient.toml", text);
  expect_same_over_ranks(scenario.string() + " --algorithm distributed");
  EXPECT_GT(results(dir_ / "one.json")["watches"][0]["actions_done"].get<int>(), 100);
}

TEST_F(MpiRun, NeighbourAggregatesEqualOneProcess) {
  // Aggregates read neighbours' values, some on another rank (gathered as each step ends), one
  // hop late; the agents of the last steps drain at the end, over ranks as in one process.
  const fs::path scenario = write("aggregate.toml",
                                  "steps = 12\n[lattice]\nkind = \"cubic\"\nsize = [6, 6, 6]\n"
                                  "[[program]]\nname = \"random_vars\"\ntuple = [2, 2, 2, 2]\n"
                                  "[[watch]]\nname = \"agg\"\naction = \"log\"\n"
                                  "text = \"modules(a b); count(n in neighbors(a): n.x1 = 0) >= 3 and "
                                  "sum(n in neighbors(b.last): n.x2) < b.x3 + 2\"\n");
  expect_same_over_ranks(scenario.string() + " --algorithm distributed");
  const nlohmann::json one = results(dir_ / "one.json");
  EXPECT_GT(one["matches"].get<int>(), 100);
  EXPECT_GT(one["watches"][0]["value_messages"].get<int>(), 0);
}

TEST_F(MpiRun, ACentralizedWatchpointIsRefusedWithTheReason) {
  const Result r = mpirun(2, "run " + scenarios_ + "/token_ring.toml --matches " + (dir_ / "m.jsonl").string());
  EXPECT_EQ(r.code, 2);
  const std::string said = "cannot run over 2 ranks: watchpoint 'token_from_nowhere' is centralized";
  EXPECT_NE(r.err.find(said), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find(said), r.err.rfind(said)) << "said once, by rank 0: " << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "m.jsonl"));
}

TEST_F(MpiRun, AProgramFailingOnTheLastRankStopsEveryRankWithItsMessage) {
  write("fail.lua",
        "program = { vars = { \"v\" } }\n"
        "function step(m)\n  m:set(\"v\", m.step)\n  if m.step == 3 and m.id == 120 then local x = nil + 1 end\nend\n");
  const fs::path scenario = write("fail.toml",
                                  "steps = 10\n[lattice]\nkind = \"cubic\"\nsize = [5, 5, 5]\n"
                                  "[[program]]\nscript = \"fail.lua\"\n");
  const Result one = run("run " + scenario.string());
  ASSERT_EQ(one.code, 1);
  ASSERT_NE(one.err.find("module 120"), std::string::npos) << one.err;
  const Result r = mpirun(3, "run " + scenario.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.err.substr(0, r.err.find("\n--") + 1), one.err) << "rank 0 says what one process says, once";
}

TEST_F(MpiRun, AnOutputRankZeroCannotOpenStopsEveryRank) {
  const Result r = mpirun(3, "run " + scenarios_ + "/table1.toml --matches /no/such/dir/m.jsonl");
  EXPECT_EQ(r.code, 2);
  const std::string said = "--matches: cannot write /no/such/dir/m.jsonl";
  EXPECT_NE(r.err.find(said), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find(said), r.err.rfind(said)) << r.err;
}

TEST_F(MpiRun, OnlyRunRunsOverRanks) {
  const Result r = mpirun(2, "check 'modules(a); (a.x = 1)'");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("only 'dwatch run' runs over several ranks"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace dw::cli_test
