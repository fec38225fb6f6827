// The session's watchpoint slots: positions the run hosts them in, and ids that outlive nothing.
#include "sim/watch_slots.h"

#include <gtest/gtest.h>

#include "tests/sim/test_programs.h"

namespace dw::sim {
namespace {

HostedWatchpoint named(const std::string& name) {
  HostedWatchpoint h{test_programs::compile("modules(a); a.v = 1")};
  h.watchpoint.name = name;
  return h;
}

std::vector<std::string> names(const WatchSlots& slots) {
  std::vector<std::string> out;
  for (const HostedWatchpoint& h : slots.hosted()) out.push_back(h.watchpoint.name);
  return out;
}

TEST(WatchSlots, PositionsAreTheRunsOrderAndIdsNameOneWatchpointOnly) {
  WatchSlots slots(std::vector{named("a"), named("b")});
  const WatchId a = slots.id(0), c = slots.add(named("c"));
  EXPECT_EQ(names(slots), (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_EQ(slots.position(c), 2u);
  EXPECT_EQ(slots.find("b"), 1u);
  EXPECT_EQ(slots.find("z"), std::nullopt);
  const WatchId b = slots.id(1);
  slots[1].matches.count(3, 4, 5);

  // Replacing: the last one takes b's place; b's id names nothing, c's moved with it.
  const WatchId b2 = slots.add(named("b"));
  slots.move_last_to(1);
  EXPECT_EQ(names(slots), (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_EQ(slots.position(b), std::nullopt);
  EXPECT_EQ(slots.position(b2), 1u);
  EXPECT_EQ(slots.position(c), 2u);
  EXPECT_EQ(slots[1].matches.counted_total(), 0u) << "what the replaced one found went with it";

  // Removing: the ones after move up; a slot taken again has a new generation.
  slots.erase(0);
  EXPECT_EQ(names(slots), (std::vector<std::string>{"b", "c"}));
  EXPECT_EQ(slots.position(c), 1u);
  const WatchId d = slots.add(named("d"));
  EXPECT_EQ(d.index, a.index) << "the slot freed last is taken again";
  EXPECT_NE(d, a);
  EXPECT_EQ(slots.position(a), std::nullopt);
  EXPECT_EQ(slots.position(b), std::nullopt);
  EXPECT_EQ(slots.position(d), 2u);
  slots.pop_back();
  EXPECT_EQ(slots.size(), 2u);
  EXPECT_EQ(slots.position(d), std::nullopt);
}

TEST(WatchSlots, MatchesAfterAStepGo) {
  MatchList list;
  for (int64_t t = 0; t < 4; ++t) {
    list.t.push_back(t);
    list.detected.push_back(t + 2);
    list.slots.push_back(static_cast<watch::ModuleId>(t));
  }
  list.count(1, 3, 7);
  list.count(2, 4, 1);
  list.drop_after(4, 1, 0);
  EXPECT_EQ(list.t, (std::vector<int64_t>{0, 1, 2}));
  EXPECT_EQ(list.slots.size(), 3u);
  EXPECT_EQ(list.counted_total(), 8u);
  list.drop_after(3, 1, 0);
  EXPECT_EQ(list.size(), 2u);
  EXPECT_EQ(list.counted_at(1), 7u);
  EXPECT_EQ(list.counted_at(2), 0u);
}

}  // namespace
}  // namespace dw::sim
