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

TEST(AgentHistory, ARanksHistoryKeepsItsOwnModulesByTheirIds) {
  // Modules 1 and 2 of the three, from frames that carry the variables of those two only (a
  // rank's, docs/design.md §12): what they read is what the whole history reads of them.
  const Watchpoint w = compile_or_die("modules(a b); (a.last.x = b.x)");
  const AgentHistory whole = six_steps("modules(a b); (a.last.x = b.x)", true);
  AgentHistory part;
  part.configure(w.program, true, 1, 2);
  Frames frames;
  const int columns[] = {0};
  for (int64_t t = 0; t < 6; ++t) {
    Frame f = frames.at(t);
    f.values = f.values.subspan(1);
    f.has_value = f.has_value.subspan(1);
    f.first_module = 1;
    part.begin_record(f);
    part.record(f, 1, 3, columns);
  }
  EXPECT_EQ(part.first(), 1u);
  EXPECT_EQ(part.held(), (2u + 1u) * 2u) << "two steps of x and one of topology, for two modules";
  for (uint32_t m : {1u, 2u})
    for (int64_t t : {4, 5}) {
      int64_t a = -1, b = -1;
      EXPECT_EQ(part.value(m, 0, t, a), whole.value(m, 0, t, b)) << m << " at " << t;
      EXPECT_EQ(a, b) << m << " at " << t;  // -1 both when unknown
      EXPECT_EQ(part.present(m, t), whole.present(m, t));
      uint32_t count = 0, whole_count = 0;
      const uint32_t* n = part.neighbors(m, t, count);
      EXPECT_EQ(n == nullptr, whole.neighbors(m, t, whole_count) == nullptr);
      if (n) {
        EXPECT_EQ(count, whole_count);
      }
    }
  int64_t v = -1;
  ASSERT_TRUE(part.value(2, 0, 4, v));
  EXPECT_EQ(v, 42);
  const int64_t* column = nullptr;
  const uint8_t* known = nullptr;
  ASSERT_TRUE(part.column(0, 5, column, known));
  EXPECT_EQ(column[0], 51) << "columns start at the first module kept";
  EXPECT_EQ(known[1], 0) << "module 2 is absent at odd steps";
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
