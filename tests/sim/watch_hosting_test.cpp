// Hosting the watchpoints (sim/watch_hosting.cpp, docs/design.md §4b, §12): a distributed watchpoint
// runs on agents with a PatternMatcher lane per (thread, block), any other reading on a detector;
// only the first can run over ranks; the actions of a step's matches are queued in watchpoint,
// match and action order, and carried out at the next step unless their module is gone, their
// value unknown or their variable missing; a watchpoint with actions observes every step.
#include "sim/watch_hosting.h"

#include <gtest/gtest.h>

#include "tests/sim/test_programs.h"

namespace dw::sim {
namespace {

using watch::Algorithm;

constexpr const char* kActing = "modules(a b); (a.v >= 0) then set b.mix = a.v + 100, remove a";
constexpr const char* kPlain = "modules(a); (a.v >= 0)";

std::unique_ptr<Model> line(uint32_t n, std::vector<std::pair<std::string, Algorithm>> watches) {
  return test_programs::gossip_model({LatticeKind::Line, {n, 1, 1}}, std::move(watches));
}

TEST(WatchHosting, ADistributedWatchRunsOnAgentsWithALanePerThreadAndBlock) {
  const auto model = line(100, {{kPlain, Algorithm::Distributed}, {kPlain, Algorithm::Centralized}});
  const BlockPlacement placement(*model, 2, nullptr, Partition::Blocks, false);
  ASSERT_EQ(placement.blocks(), 4u);
  WatchHosting hosting(*model, model->watches, placement, 2, nullptr);
  ASSERT_EQ(hosting.size(), 2u);
  const WatchState agents = hosting.initial_state(0), detector = hosting.initial_state(1);
  EXPECT_TRUE(agents.agents.has_value());
  EXPECT_EQ(agents.detector, nullptr);
  EXPECT_EQ(agents.in_flight.size(), 2u * 4);
  EXPECT_NE(detector.detector, nullptr);
  EXPECT_FALSE(detector.agents.has_value());
  EXPECT_TRUE(detector.in_flight.empty());
  EXPECT_EQ(hosting.lanes(0).size(), 2u * 4);
  EXPECT_TRUE(hosting.lanes(1).empty());
  // Over ranks no process holds the whole ensemble a detector observes.
  EXPECT_NE(why_not_over_ranks(*model).find("watchpoint 'w' is centralized"), std::string::npos);
  EXPECT_EQ(why_not_over_ranks(std::span(model->watches).first(1)), "");
}

TEST(WatchHosting, AWatchWithActionsObservesEveryStep) {
  const auto model = line(4, {{kActing, Algorithm::Distributed}, {kPlain, Algorithm::Distributed}});
  const BlockPlacement placement(*model, 1, nullptr, Partition::Blocks, false);
  const WatchHosting hosting(*model, model->watches, placement, 1, nullptr);
  const std::vector<uint8_t> none{0, 0}, second{0, 1};
  EXPECT_TRUE(hosting.observes(0, {}) && hosting.observes(1, {}));  // none marked: all
  EXPECT_TRUE(hosting.observes(0, none));                           // its actions are part of the simulation
  EXPECT_FALSE(hosting.observes(1, none));
  EXPECT_TRUE(hosting.observes(1, second));
}

TEST(WatchHosting, ActionsAreQueuedInWatchOrderThenMatchOrderThenActionOrder) {
  const auto model =
      line(4, {{kActing, Algorithm::Distributed}, {kPlain, Algorithm::Distributed}, {kActing, Algorithm::Distributed}});
  const BlockPlacement placement(*model, 1, nullptr, Partition::Blocks, false);
  const WatchHosting hosting(*model, model->watches, placement, 1, nullptr);
  std::vector<WatchStepOutput> out(3);
  out[0].slots = {2, 3, 0, 1};  // two matches (a b), each with its two actions' values
  out[0].actions = {{7, true}, {0, true}, {8, false}, {0, true}};
  out[1].slots = {1};  // no actions: nothing to queue
  out[2].slots = {1, 2};
  out[2].actions = {{9, true}, {0, true}};
  State state;
  hosting.queue_actions(state, out);
  const int mix = model->column("mix");
  // watch, module, column, remove, known, value
  EXPECT_EQ(state.actions, (std::vector<PendingAction>{{0, 3, mix, false, true, 7},
                                                       {0, 2, -1, true, true, 0},
                                                       {0, 1, mix, false, false, 8},
                                                       {0, 0, -1, true, true, 0},
                                                       {2, 2, mix, false, true, 9},
                                                       {2, 1, -1, true, true, 0}}));
}

TEST(WatchHosting, AnActionOnAGoneModuleOrWithAnUnknownValueOrVariableIsSkipped) {
  const auto model = line(4, {{kActing, Algorithm::Distributed}});
  const BlockPlacement placement(*model, 1, nullptr, Partition::Blocks, false);
  const WatchHosting hosting(*model, model->watches, placement, 1, nullptr);
  const int mix = model->column("mix");
  const size_t v = model->variable_count();
  State state;
  state.present.assign(4, 1);
  state.graph = model->lattice.graph;
  state.values.assign(4 * v, -1);
  state.watches.push_back(hosting.initial_state(0));
  state.actions = {{0, 1, mix, false, true, 42},   // done
                   {0, 2, mix, false, false, 43},  // skipped: its value is unknown
                   {0, 3, -1, false, true, 44},    // skipped: the model has no such variable
                   {0, 0, -1, true, true, 0},      // done: module 0 leaves
                   {0, 0, mix, false, true, 45}};  // skipped: module 0 is gone by now
  StaticLatticeWorld world;
  hosting.act(state, world);
  EXPECT_EQ(state.watches[0].actions_done, 2u);
  EXPECT_EQ(state.watches[0].actions_skipped, 3u);
  EXPECT_EQ(state.values[1 * v + size_t(mix)], 42);
  EXPECT_EQ(state.values[2 * v + size_t(mix)], -1);
  EXPECT_EQ(state.values[0 * v + size_t(mix)], -1);
  EXPECT_EQ(state.present, (std::vector<uint8_t>{0, 1, 1, 1}));
  EXPECT_TRUE(state.graph->neighbors(1).size() == 1 && state.graph->neighbors(1)[0] == 2);
  EXPECT_TRUE(state.actions.empty());
}

}  // namespace
}  // namespace dw::sim
