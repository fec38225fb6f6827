#include "watch/agent_history.h"

#include <gtest/gtest.h>

#include <string>

#include "test_ensemble.h"

namespace dw::watch {
namespace {

using testing::compile_or_die;

// Three modules on a path 0 - 1 - 2, one variable x = 10 * step + module; module 2 is absent at
// odd steps (and then lists no neighbours).
struct Frames {
  std::vector<uint8_t> present;
  std::vector<int64_t> values;
  std::vector<uint8_t> has{1, 1, 1};
  std::vector<uint32_t> begin, ids;

  Frame at(int64_t step) {
    const bool two = step % 2 == 0;
    present = {1, 1, uint8_t(two)};
    values = {10 * step, 10 * step + 1, 10 * step + 2};
    begin = two ? std::vector<uint32_t>{0, 1, 3, 4} : std::vector<uint32_t>{0, 1, 2, 2};
    ids = two ? std::vector<uint32_t>{1, 0, 2, 1} : std::vector<uint32_t>{1, 0};
    Frame f;
    f.step = step;
    f.present = present;
    f.values = values;
    f.has_value = has;
    f.nbr_begin = begin;
    f.nbrs = ids;
    f.variable_count = 1;
    return f;
  }
};

void record(AgentHistory& h, const Frame& f) {
  const int columns[] = {0};
  h.begin_record(f);
  // In two blocks, as the runtime's threads record them.
  h.record(f, 0, 2, columns);
  h.record(f, 2, 3, columns);
}

// The history a watchpoint keeps of the first six frames.
AgentHistory six_steps(const std::string& watchpoint, bool temporal_spans) {
  const Watchpoint w = compile_or_die(watchpoint);
  AgentHistory h;
  h.configure(w.program, temporal_spans, 0, 3);
  Frames frames;
  for (int64_t t = 0; t < 6; ++t) record(h, frames.at(t));
  return h;
}

TEST(AgentHistory, KeepsExactlyTheStepsTheSpansNeed) {
  // x is read at t - 2, t - 1 and t: three steps of values; neighbour sets only at t.
  const AgentHistory h = six_steps("modules(a b); (a.last.last.x = b.last.x) and (a.x = 0)", true);
  int64_t v = -1;
  EXPECT_FALSE(h.value(0, 0, 2, v)) << "step 2 is forgotten: only 3..5 are held";
  ASSERT_TRUE(h.value(1, 0, 3, v));
  EXPECT_EQ(v, 31);
  ASSERT_TRUE(h.value(2, 0, 4, v));
  EXPECT_EQ(v, 42);
  EXPECT_FALSE(h.value(2, 0, 5, v)) << "module 2 is absent at odd steps";
  EXPECT_FALSE(h.value(0, 0, 6, v)) << "not recorded yet";

  uint32_t count = 0;
  const uint32_t* n = h.neighbors(1, 5, count);
  ASSERT_NE(n, nullptr);
  EXPECT_EQ(std::vector<uint32_t>(n, n + count), (std::vector<uint32_t>{0}));
  EXPECT_EQ(h.neighbors(2, 5, count), nullptr);
  EXPECT_EQ(h.neighbors(1, 4, count), nullptr) << "neighbour sets are held for one step";
  EXPECT_TRUE(h.present(0, 5));
  EXPECT_FALSE(h.present(2, 5));
  EXPECT_EQ(h.held(), (3u + 1u) * 3u) << "three steps of x and one of topology, for each module";
}

TEST(AgentHistory, WithoutSpansKeepsTheWholeRun) {
  const AgentHistory h = six_steps("modules(a b); (a.x = 0)", false);
  int64_t v = -1;
  ASSERT_TRUE(h.value(2, 0, 0, v));
  EXPECT_EQ(v, 2);
  uint32_t count = 0;
  const uint32_t* n = h.neighbors(1, 2, count);
  ASSERT_NE(n, nullptr);
  EXPECT_EQ(std::vector<uint32_t>(n, n + count), (std::vector<uint32_t>{0, 2}));
}

TEST(AgentHistory, AGraphThatStaysTheSameIsHeldOnce) {
  const Watchpoint w = compile_or_die("modules(a b); (a.x = 0)");
  const Program& p = w.program;
  Frames frames;
  auto history_bytes = [&](int steps, bool lent, bool changing) {
    AgentHistory h;
    h.configure(p, false, 0, 3);
    auto owner = std::make_shared<int>(0);
    for (int64_t t = 0; t < steps; ++t) {
      Frame f = frames.at(changing ? t : 0);
      f.step = t;
      if (lent) f.topology = owner;
      record(h, f);
    }
    // Each step's graph reads as that step's, whether copied or shared.
    uint32_t count = 0;
    EXPECT_NE(h.neighbors(1, steps - 1, count), nullptr);
    EXPECT_EQ(count, changing && (steps - 1) % 2 ? 1u : 2u);
    return h.bytes();
  };
  const size_t values_and_presence = history_bytes(40, true, false);
  EXPECT_EQ(history_bytes(40, false, false) - values_and_presence,
            history_bytes(2, false, false) - history_bytes(2, true, false))
      << "an unchanged graph copied once, whatever the steps";
  EXPECT_GT(history_bytes(40, false, true), history_bytes(40, false, false)) << "a changing graph is copied per change";
}

}  // namespace
}  // namespace dw::watch
