#include "watch/simultaneous_detector.h"

#include <gtest/gtest.h>

#include "cube.h"

namespace dw::watch {
namespace {

using testing::compile_or_die;
using testing::Match;
using testing::TestEnsemble;

DetectorOptions simultaneous(GroupShape shape) {
  DetectorOptions o;
  o.shape = shape;
  o.states = States::Simultaneous;
  return o;
}

TEST(SimultaneousDetector, FindsTheCentralizedCountsOnTheTableICube) {
  const TestEnsemble e = testing::cube_ensemble(10, 1);
  const Watchpoint w = compile_or_die("modules(a b c d); (a.x = 0)");
  // Per step on the 10^3 cube: 110,472 chains of 4, 576,672 prefix-connected orders, and the
  // 62,418 connected 4-module groups in all 24 slot assignments.
  const std::pair<GroupShape, size_t> expected[] = {
      {GroupShape::Chain, 110'472}, {GroupShape::Ordered, 576'672}, {GroupShape::Any, 62'418u * 24}};
  testing::TestEnsemble::FrameData data;
  const Frame frame = e.frame(0, data);
  for (const auto& [shape, count] : expected) {
    DetectorOptions central;
    central.shape = shape;
    for (const auto& [algorithm, options] :
         {std::pair{Algorithm::Centralized, central}, std::pair{Algorithm::Distributed, simultaneous(shape)}}) {
      size_t found = 0;
      auto d = make_detector(
          algorithm, w, e.universe(), options,
          [&](int64_t, std::span<const ModuleId> ids, std::span<const Value>) { found += ids.size() / 4; });
      d->observe(frame);
      d->finish();
      EXPECT_EQ(found, count) << algorithm_name(algorithm) << " " << shape_name(shape);
      EXPECT_EQ(d->stats().lost, 0u);
    }
  }
}

// A line 0 - 1 - 2: the token-ring watchpoint of Fig. 3 read at one step finds nothing where the
// paper's consistent reading, b.last one step later than a's, does.
TEST(SimultaneousDetector, ReadsEverySlotAtTheStartStep) {
  TestEnsemble e(3, {"v"});
  for (int t = 0; t < 3; ++t) {
    e.set(t, 0, {{"v", t}}, {1});
    e.set(t, 1, {{"v", t}}, {0, 2});
    e.set(t, 2, {{"v", t}}, {1});
  }
  const Watchpoint w = compile_or_die("modules(a b); (a.v = b.v)");
  std::set<Match> want;
  for (int64_t t = 0; t < 3; ++t)
    for (auto [a, b] : {std::pair{0u, 1u}, {1u, 0u}, {1u, 2u}, {2u, 1u}}) want.insert({t, {a, b}});
  EXPECT_EQ(e.run(Algorithm::Distributed, w, simultaneous(GroupShape::Chain)), want);
  EXPECT_TRUE(e.run(Algorithm::Distributed, w).empty()) << "consistent states compare v at t and t + 1";
}

// Ordered groups walk back: in a star 1 - 0 - 2 the binding (a=1, b=0, c=2) fills c from b's
// neighbours, and (a=0, b=1, c=2) fills c by walking from 1 back to 0 and on to 2.
TEST(SimultaneousDetector, OrderedGroupsWalkBackThroughTheGroupAndAreDecidedWithinTheLatency) {
  TestEnsemble e(3, {"v"});
  const int steps = 6;
  for (int t = 0; t < steps; ++t) {
    e.set(t, 0, {{"v", 1}}, {1, 2});
    e.set(t, 1, {{"v", 1}}, {0});
    e.set(t, 2, {{"v", 1}}, {0});
  }
  const Watchpoint w = compile_or_die("modules(a b c); (a.v = 1) and (b.v = 1) and (c.v = 1)");
  auto d = make_detector(Algorithm::Distributed, w, e.universe(), simultaneous(GroupShape::Ordered), nullptr);
  EXPECT_EQ(d->lag(), 3) << "L = k(k - 1)/2 hops for 3 slots";
  const auto all = e.run(Algorithm::Distributed, w, simultaneous(GroupShape::Ordered));
  EXPECT_TRUE(all.count({0, {0, 1, 2}})) << "the walk back to 0";
  EXPECT_TRUE(all.count({0, {1, 0, 2}}));
  DetectorOptions central;
  central.shape = GroupShape::Ordered;
  EXPECT_EQ(all, e.run(Algorithm::Centralized, w, central));
  DetectorStats stats;
  e.run(Algorithm::Distributed, w, simultaneous(GroupShape::Ordered), &stats);
  EXPECT_GT(stats.messages, stats.matches) << "walking back costs hops";
}

// A link that breaks before the hop that needs it loses the PatternMatcher, and says so.
TEST(SimultaneousDetector, AHopOverALinkGoneByThenIsLostAndCounted) {
  TestEnsemble e(3, {"v"});
  e.set(0, 0, {{"v", 1}}, {1});
  e.set(0, 1, {{"v", 1}}, {0, 2});
  e.set(0, 2, {{"v", 1}}, {1});
  // At step 1, 1 and 2 drift apart: the chain 0 - 1 - 2 of step 0 cannot make its second hop.
  e.set(1, 0, {{"v", 1}}, {1});
  e.set(1, 1, {{"v", 1}}, {0});
  e.set(1, 2, {{"v", 1}}, {});
  e.set(2, 0, {{"v", 1}}, {1});
  e.set(2, 1, {{"v", 1}}, {0});
  e.set(2, 2, {{"v", 1}}, {});
  const Watchpoint w = compile_or_die("modules(a b c); (a.v = 1)");
  DetectorOptions central;
  central.shape = GroupShape::Chain;
  const auto want = e.run(Algorithm::Centralized, w, central);
  ASSERT_TRUE(want.count({0, {0, 1, 2}}));
  DetectorStats stats;
  const auto got = e.run(Algorithm::Distributed, w, simultaneous(GroupShape::Chain), &stats);
  EXPECT_FALSE(got.count({0, {0, 1, 2}}));
  EXPECT_TRUE(got.count({0, {2, 1, 0}})) << "its first hop, 1 -> 0, still exists";
  EXPECT_GT(stats.lost, 0u);
  for (const Match& m : got) EXPECT_TRUE(want.count(m));
}

TEST(SimultaneousDetector, ACloneMidRunGoesOnAsTheRunItWasCopiedFrom) {
  const TestEnsemble e = testing::cube_ensemble(3, 6);
  const Watchpoint w = compile_or_die("modules(a b c); (a.x = 0) and not neighbor(a c)");
  for (GroupShape shape : {GroupShape::Chain, GroupShape::Ordered, GroupShape::Any}) {
    using Reported = std::pair<int64_t, std::vector<ModuleId>>;
    std::vector<Reported> straight, cloned;
    auto d = make_detector(Algorithm::Distributed, w, e.universe(), simultaneous(shape),
                           [&](int64_t t, std::span<const ModuleId> ids, std::span<const Value>) {
                             straight.emplace_back(t, std::vector<ModuleId>(ids.begin(), ids.end()));
                           });
    auto copy = e.feed_and_clone(*d, 2, [&](int64_t t, std::span<const ModuleId> ids, std::span<const Value>) {
      cloned.emplace_back(t, std::vector<ModuleId>(ids.begin(), ids.end()));
    });
    ASSERT_FALSE(cloned.empty());
    const std::vector<Reported> tail(straight.end() - static_cast<ptrdiff_t>(cloned.size()), straight.end());
    EXPECT_EQ(cloned, tail) << shape_name(shape);
  }
}

}  // namespace
}  // namespace dw::watch
