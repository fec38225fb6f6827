#include "sim/synthetic_trace.h"
#include "tests/sim/trace_frames.h"

#include <gtest/gtest.h>

#include "watch/make_detector.h"
#include "watch/watchpoint.h"

namespace dw::sim {
namespace {

watch::Watchpoint fig6() {
  auto r = watch::compile_watchpoint(
      "fig6", watch::SourceText("fig6", "modules(a b c d); (a.x1 = 0) and (b.x2 = 0) and (c.x3 = 0) and (d.x4 = 0)"));
  return std::move(std::get<watch::Watchpoint>(r));
}

uint64_t count_matches(const Trace& trace, watch::Algorithm a, const watch::Watchpoint& w,
                       std::vector<uint64_t>* per_t) {
  uint64_t total = 0;
  const test::TraceFrames frames(trace);
  auto d = watch::make_detector(a, w, frames.universe(), {},
                                [&](int64_t t, std::span<const watch::ModuleId> ids, std::span<const watch::Value>) {
                                  total += ids.size() / 4;
                                  if (per_t) {
                                    if (per_t->size() <= static_cast<size_t>(t))
                                      per_t->resize(static_cast<size_t>(t) + 1);
                                    (*per_t)[static_cast<size_t>(t)] += ids.size() / 4;
                                  }
                                });
  for (const watch::Frame& f : frames.all()) d->observe(f);
  return total;
}

TEST(SyntheticTrace, CubeHasSixNeighboursInsideAndThreeAtCorners) {
  CubicRandomVars spec;
  spec.steps = 1;
  const Trace t = make_cubic_random_vars(spec);
  EXPECT_EQ(t.universe().module_count(), 1000u);
  const test::TraceFrames frames(t);
  const watch::Frame& f = frames.frame(0);
  EXPECT_EQ(f.neighbors(0).size(), 3u);
  EXPECT_EQ(f.neighbors(1 + 10 * (1 + 10 * 1)).size(), 6u);
  EXPECT_EQ(f.nbrs.size(), 2u * 2700) << "2,700 face pairs, each listed from both sides";
}

// The reference counts for the 10x10x10 cube: every binding matches when all x_i = 0.
TEST(SyntheticTrace, CubeHasTheExpectedChainAndBindingCounts) {
  CubicRandomVars spec;
  spec.steps = 4;
  spec.maxima = {1, 1, 1, 1};
  const Trace t = make_cubic_random_vars(spec);
  const watch::Watchpoint w = fig6();
  std::vector<uint64_t> central;
  count_matches(t, watch::Algorithm::Centralized, w, &central);
  ASSERT_EQ(central.size(), 4u);
  for (uint64_t c : central) EXPECT_EQ(c, 576'672u) << "prefix-connected bindings per step";
  std::vector<uint64_t> chains;
  count_matches(t, watch::Algorithm::Distributed, w, &chains);
  ASSERT_EQ(chains.size(), 1u) << "only t = 0 completes its chain within 4 steps";
  EXPECT_EQ(chains[0], 110'472u) << "linear 4-chains";
}

TEST(SyntheticTrace, SameSeedSameTraceOtherSeedOtherTrace) {
  CubicRandomVars spec;
  spec.nx = spec.ny = spec.nz = 4;
  spec.steps = 5;
  spec.maxima = {2, 3, 4, 5};
  const Trace a = make_cubic_random_vars(spec), b = make_cubic_random_vars(spec);
  spec.seed = 2;
  const Trace c = make_cubic_random_vars(spec);
  bool differs = false;
  const test::TraceFrames framesa(a), framesb(b), framesc(c);
  for (int64_t s = 0; s < a.step_count(); ++s) {
    const watch::Frame &fa = framesa.frame(s), &fb = framesb.frame(s), &fc = framesc.frame(s);
    EXPECT_TRUE(std::equal(fa.values.begin(), fa.values.end(), fb.values.begin()));
    differs |= !std::equal(fa.values.begin(), fa.values.end(), fc.values.begin());
    for (size_t i = 0; i < fa.values.size(); ++i) EXPECT_LT(fa.values[i], spec.maxima[i % 4]);
  }
  EXPECT_TRUE(differs);
}

TEST(SyntheticTrace, TupleHalvesTheSurvivorsAsThePaperSays) {
  // [2:1:1:1] keeps about half of [1:1:1:1]'s matches (paper Table I: 6.2M vs 3.1M).
  CubicRandomVars spec;
  spec.steps = 10;
  spec.maxima = {1, 1, 1, 1};
  const watch::Watchpoint w = fig6();
  const uint64_t all = count_matches(make_cubic_random_vars(spec), watch::Algorithm::Distributed, w, nullptr);
  spec.maxima = {2, 1, 1, 1};
  const uint64_t half = count_matches(make_cubic_random_vars(spec), watch::Algorithm::Distributed, w, nullptr);
  EXPECT_NEAR(static_cast<double>(half) / static_cast<double>(all), 0.5, 0.03);
}

}  // namespace
}  // namespace dw::sim
