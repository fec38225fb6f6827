// Spanning-tree aggregation and landmark routing (scenarios/programs/aggregation_routing.cpp) converge to
// the BFS distances and to the root counting every module.
#include <gtest/gtest.h>

#include "tests/scenarios/scenario_helpers.h"

namespace dw::scenarios {
namespace {

TEST(AggregationRouting, ConvergesToBfsDistancesAndTheRootCountsEveryModule) {
  for (auto [kind, size, root] : {std::tuple{"cubic", "[6, 5, 4]", 0}, {"hex2d", "[9, 7]", 31}, {"ring", "[11]", 4}}) {
    SCOPED_TRACE(kind);
    Scenario s = test::load(std::string("[lattice]\nkind = \"") + kind + "\"\nsize = " + size +
                            "\n[[program]]\nname = \"aggregation_routing\"\nroot = " + std::to_string(root) +
                            "\nlandmarks = 2\n");
    test::History dist, sum, parent, lm1;
    sim::Model& model = *s.model;
    auto d = test::record(model, "dist", dist), su = test::record(model, "sum", sum),
         p = test::record(model, "parent", parent), l = test::record(model, "lm1", lm1);
    sim::Session run(model, *s.world, {.threads = 2});
    run.run_until(60, [&](const sim::State& st, const sim::StepOutput& o) {
      d(st, o);
      su(st, o);
      p(st, o);
      l(st, o);
    });
    const sim::NeighborGraph& g = *model.lattice.graph;
    const auto from_root = test::bfs(g, sim::ModuleId(root));
    const uint32_t n = g.module_count();
    const sim::ModuleId landmark1 = sim::ModuleId(3 * n / 4);
    const auto from_landmark = test::bfs(g, landmark1);
    for (sim::ModuleId m = 0; m < n; ++m) {
      EXPECT_EQ(dist(59, m), from_root[m]) << m;
      EXPECT_EQ(lm1(59, m), from_landmark[m]) << m;
      if (m != sim::ModuleId(root)) {
        ASSERT_GE(parent(59, m), 0);
        EXPECT_EQ(from_root[size_t(parent(59, m))], from_root[m] - 1) << "a parent is one hop closer";
      }
    }
    EXPECT_EQ(sum(59, sim::ModuleId(root)), int64_t(n));
    EXPECT_LT(sum(3, sim::ModuleId(root)), int64_t(n)) << "it takes time";
  }
}

TEST(AggregationRouting, ShippedScenarioNeverLosesCount) {
  auto loaded = load_scenario(std::string(DWATCH_SCENARIOS_DIR) + "/aggregation_routing.toml");
  ASSERT_TRUE(std::holds_alternative<Scenario>(loaded));
  Scenario& s = std::get<Scenario>(loaded);
  sim::Session run(*s.model, *s.world, {.threads = s.threads});
  run.run_until(s.steps);
  EXPECT_EQ(run.match_count(0), 0u);
  const int sum = s.model->column("sum");
  EXPECT_EQ(run.state().values[size_t(sum)], 1000) << "module 0, the root, counts the cube";
}

}  // namespace
}  // namespace dw::scenarios
