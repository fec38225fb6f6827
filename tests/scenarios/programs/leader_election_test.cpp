// 2-hop leader election (scenarios/programs/leader_election.cpp).
//
// Why the correct variant is safe: say u is elected at step t_u and w at t_w >= t_u, within two
// hops. If they are two hops apart through v: w was not covered at t_w, so v had not heard of u
// as a leader by t_w - 1, i.e. t_w - 2 < t_u. At t_u, u's rival included v's 1-hop best as of
// t_u - 1, which counted w (undecided at t_u - 2), so p_u > p_w. At t_w, w's rival counted u
// (undecided at t_w - 2 < t_u) the same way, so w could not win: a contradiction. Adjacent
// modules see each other's status one step late, and the same argument applies. The tests below
// check the outcome with a BFS, on several seeds and sizes.
#include <gtest/gtest.h>

#include "tests/scenarios/scenario_helpers.h"

namespace dw::scenarios {
namespace {

std::string scenario(uint32_t nx, uint32_t ny, bool bug, const std::string& algorithm, const std::string& action) {
  return "[lattice]\nkind = \"hex2d\"\nsize = [" + std::to_string(nx) + ", " + std::to_string(ny) +
         "]\n[[program]]\nname = \"leader_election\"\nbug = " + (bug ? "true" : "false") +
         "\n[[watch]]\nname = \"two_leaders\"\ntext = \"modules(a b c); (a.isLeader = 1) and (c.isLeader = 1)\"\n"
         "algorithm = \"" +
         algorithm + "\"\naction = \"" + action + "\"\n";
}

TEST(LeaderElection, CorrectVariantNeverHasTwoLeadersWithinTwoHopsAndCoversEveryone) {
  for (auto [nx, ny] : {std::pair{12u, 10u}, {7u, 5u}, {20u, 3u}, {1u, 9u}})
    for (uint64_t seed : {1u, 2u, 3u, 17u})
      for (const char* algorithm : {"distributed", "centralized"}) {
        SCOPED_TRACE(std::to_string(nx) + "x" + std::to_string(ny) + " seed " + std::to_string(seed) + " " + algorithm);
        Scenario s = test::load(scenario(nx, ny, false, algorithm, "log"), {seed, std::nullopt});
        test::History leader;
        sim::Session run(*s.model, *s.world, {.threads = 1});
        run.run_until(200, test::record(*s.model, "isLeader", leader));
        EXPECT_EQ(run.current() + 1, 200);
        EXPECT_EQ(run.match_count(0), 0u);
        // The end state: leaders pairwise at least three hops apart, everyone within two of one.
        const sim::NeighborGraph& g = *s.model->lattice.graph;
        std::vector<int> nearest(g.module_count(), 1 << 20);
        int leaders = 0;
        for (sim::ModuleId m = 0; m < g.module_count(); ++m) {
          if (!leader(199, m)) continue;
          ++leaders;
          const auto d = test::bfs(g, m);
          for (sim::ModuleId o = 0; o < g.module_count(); ++o) {
            if (o != m && leader(199, o)) {
              EXPECT_GE(d[o], 3) << m << " and " << o;
            }
            nearest[o] = std::min(nearest[o], d[o]);
          }
        }
        EXPECT_GT(leaders, 0);
        for (sim::ModuleId o = 0; o < g.module_count(); ++o) EXPECT_LE(nearest[o], 2) << "module " << o << " uncovered";
      }
}

TEST(LeaderElection, BuggyVariantGivesTwoLeadersExactlyTwoHopsApart) {
  for (const char* algorithm : {"distributed", "centralized"}) {
    SCOPED_TRACE(algorithm);
    Scenario s = test::load(scenario(12, 10, true, algorithm, "log"));
    test::History leader;
    sim::Session run(*s.model, *s.world, {.threads = 2});
    run.run_until(40, test::record(*s.model, "isLeader", leader));
    const sim::MatchList& matches = run.matches(0);
    ASSERT_GT(matches.size(), 0u);
    const bool distributed = std::string(algorithm) == "distributed";
    const sim::NeighborGraph& g = *s.model->lattice.graph;
    for (size_t i = 0; i < matches.size(); ++i) {
      const int64_t t = matches.t[i];
      const sim::ModuleId a = matches.slots[3 * i], b = matches.slots[3 * i + 1], c = matches.slots[3 * i + 2];
      // a fills at t, c at t + 2 (distributed, consistent states) or both at t (centralized).
      EXPECT_EQ(leader(t, a), 1);
      EXPECT_EQ(leader(distributed ? t + 2 : t, c), 1);
      EXPECT_EQ(test::bfs(g, a)[c], 2) << "a=" << a << " c=" << c << " at t=" << t;
      EXPECT_TRUE(g.adjacent(a, b) || (!distributed && g.adjacent(b, c)));
      if (distributed) {
        EXPECT_TRUE(g.adjacent(b, c));
      }
    }
  }
}

TEST(LeaderElection, ShippedScenarioPausesOnTheFig2Violation) {
  auto loaded = load_scenario(std::string(DWATCH_SCENARIOS_DIR) + "/leader_election.toml");
  ASSERT_TRUE(std::holds_alternative<Scenario>(loaded));
  Scenario& s = std::get<Scenario>(loaded);
  sim::Session run(*s.model, *s.world, {.threads = s.threads});
  const auto pause = run.run_until(s.steps);
  ASSERT_TRUE(pause);
  EXPECT_EQ(pause->detected, pause->t + 2) << "three slots, distributed: two steps to fill them";
  EXPECT_EQ(test::bfs(*s.model->lattice.graph, pause->group[0])[pause->group[2]], 2);
  EXPECT_TRUE(run.seek(pause->t));
}

}  // namespace
}  // namespace dw::scenarios
