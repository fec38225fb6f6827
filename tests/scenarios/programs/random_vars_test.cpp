// The Table I host (scenarios/programs/random_vars.cpp) through the runtime draws exactly the numbers of
// the synthetic trace, so live detection and replay of that trace agree, for both algorithms.
#include <gtest/gtest.h>

#include "sim/synthetic_trace.h"
#include "tests/scenarios/scenario_helpers.h"
#include "watch/make_detector.h"

namespace dw::scenarios {
namespace {

TEST(RandomVars, LiveRunMatchesTheSyntheticTableITrace) {
  const char* fig6 = "modules(a b c d); (a.x1 = 1) and (b.x2 = 1) and (c.x3 = 1) and (d.x4 = 1)";
  for (const char* algorithm : {"distributed", "centralized"}) {
    SCOPED_TRACE(algorithm);
    Scenario s = test::load(std::string("seed = 3\n[lattice]\nkind = \"cubic\"\nsize = [6, 6, 6]\n[[program]]\n"
                                        "name = \"random_vars\"\ntuple = [2, 2, 3, 2]\n[[watch]]\nname = \"fig6\"\n"
                                        "action = \"count\"\nalgorithm = \"") +
                            algorithm + "\"\ntext = \"" + fig6 + "\"\n");
    sim::Session run(*s.model, *s.world, {.threads = 2});
    run.run_until(30);

    sim::CubicRandomVars spec;
    spec.nx = spec.ny = spec.nz = 6;
    spec.steps = 30;
    spec.maxima = {2, 2, 3, 2};
    spec.seed = 3;
    const sim::Trace trace = sim::make_cubic_random_vars(spec);
    auto frames = std::get<sim::FrameReader>(sim::FrameReader::make(trace, std::nullopt, sim::default_frame_budget()));
    uint64_t replayed = 0;
    auto detector =
        watch::make_detector(s.model->watches[0].algorithm, s.model->watches[0].watchpoint, frames.universe(), {},
                             [&](int64_t, std::span<const watch::ModuleId> ids, std::span<const watch::Value>) {
                               replayed += ids.size() / 4;
                             });
    for (int64_t t = 0; t < trace.step_count(); ++t) detector->observe(frames.frame(t));
    EXPECT_GT(replayed, 0u);
    EXPECT_EQ(run.match_count(0), replayed);
    EXPECT_EQ(run.stats(0).created, detector->stats().created);
  }
}

TEST(RandomVars, ValuesStayInRange) {
  Scenario s =
      test::load("[lattice]\nkind = \"line\"\nsize = [50]\n[[program]]\nname = \"random_vars\"\ntuple = [1, 3]\n");
  test::History x1, x2;
  auto a = test::record(*s.model, "x1", x1), b = test::record(*s.model, "x2", x2);
  sim::Session run(*s.model, *s.world, {.threads = 1});
  run.run_until(20, [&](const sim::State& st, const sim::StepOutput& o) {
    a(st, o);
    b(st, o);
  });
  std::array<int, 3> seen{};
  for (int64_t t = 0; t < 20; ++t)
    for (sim::ModuleId m = 0; m < 50; ++m) {
      EXPECT_EQ(x1(t, m), 0);
      ASSERT_GE(x2(t, m), 0);
      ASSERT_LT(x2(t, m), 3);
      ++seen[size_t(x2(t, m))];
    }
  for (int c : seen) EXPECT_GT(c, 250) << "roughly uniform over 1000 draws";
}

}  // namespace
}  // namespace dw::scenarios
