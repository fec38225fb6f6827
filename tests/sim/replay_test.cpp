#include "sim/replay.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "watch/watchpoint.h"

namespace dw::sim {
namespace {

std::string file_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

HostedWatchpoint hosted(const std::string& name, const std::string& text, watch::Algorithm algorithm) {
  auto compiled = watch::compile_watchpoint(name, watch::SourceText(name, text));
  EXPECT_TRUE(std::holds_alternative<watch::Watchpoint>(compiled));
  return {std::get<watch::Watchpoint>(std::move(compiled)), algorithm, MatchAction::Log, {}};
}

// Two watchpoints with different lags over a conformance trace: each one's matches are those of
// the independent reference, each found `lag` steps after its watch step, and released in order.
// A trace of a few lines far apart names millions of empty steps, each costing every module it
// names: refused past its budget, which a trace whose steps hold its lines stays far below.
TEST(Replay, MostlyEmptyStepsOverTheBudgetAreRefused) {
  auto trace = [](int64_t last_step, int modules) {
    std::string text = "{\"t\":0,\"m\":0,\"vars\":{\"x\":1},\"nbrs\":[";
    for (int m = 1; m < modules; ++m) text += (m > 1 ? "," : "") + std::to_string(m);
    text += "]}\n{\"t\":" + std::to_string(last_step) + ",\"m\":0,\"vars\":{},\"nbrs\":[]}\n";
    return std::get<Trace>(read_trace_text("t", text));
  };
  EXPECT_EQ(replay_work_problem(trace(999'999, 1000)), "") << "10^9 module-steps: the floor";
  const std::string why = replay_work_problem(trace(1'000'000, 1000));
  EXPECT_NE(why.find("its 1000001 steps of 1000 modules"), std::string::npos) << why;
  EXPECT_NE(why.find("mostly empty"), std::string::npos) << why;
  EXPECT_EQ(replay_work_problem(trace(1'000'000, 1000), 2'000'000'000), "") << "a limit given";
  EXPECT_NE(replay_work_problem(trace(10, 1000), 5000), "");
  // 1,000 module-steps a line: a trace with every module at every step is far below.
  std::string dense;
  for (int t = 0; t < 50; ++t)
    for (int m = 0; m < 40; ++m)
      dense += "{\"t\":" + std::to_string(t) + ",\"m\":" + std::to_string(m) + ",\"vars\":{},\"nbrs\":[]}\n";
  EXPECT_EQ(replay_work_problem(std::get<Trace>(read_trace_text("t", dense)), 2000), "");
}

// A trace of three lines, the last at step 100,000, names 100,001 steps: each watchpoint's per-step
// series keeps the three where something happened, not every step (12 watchpoints over a line at
// step 9,999,999 held 3 GB), while the totals count every step.
TEST(Replay, TheSeriesKeepOnlyTheStepsWhereSomethingHappened) {
  const std::string text =
      "{\"t\":0,\"m\":0,\"vars\":{\"x\":1},\"nbrs\":[]}\n"
      "{\"t\":1,\"m\":0,\"vars\":{\"x\":1},\"nbrs\":[]}\n"
      "{\"t\":100000,\"m\":0,\"vars\":{\"x\":1},\"nbrs\":[]}\n";
  const Trace trace = std::get<Trace>(read_trace_text("t", text));
  std::vector<HostedWatchpoint> watches;
  for (int i = 0; i < 3; ++i)
    watches.push_back(hosted("w" + std::to_string(i), "modules(a); (a.x = 1)", watch::Algorithm::Centralized));
  auto made = FrameReader::make(trace, read_variables(watches), default_frame_budget());
  ASSERT_TRUE(std::holds_alternative<FrameReader>(made));
  const std::vector<watch::DetectorStats> stats =
      replay(std::get<FrameReader>(made), trace.step_count(), watches,
             [](size_t, int64_t, int64_t, std::span<const watch::ModuleId>, std::span<const watch::Value>) {});
  for (const watch::DetectorStats& st : stats) {
    EXPECT_EQ(st.observed_steps, 100001u);
    EXPECT_EQ(st.matches, 3u);
    ASSERT_EQ(st.steps.size(), 3u);
    EXPECT_EQ(st.steps.back().step, 100000);
    EXPECT_FALSE(st.steps_truncated);
  }
}

TEST(Replay, EachWatchpointFindsTheReferencesMatchesAtItsLag) {
  const std::string dir = std::string(DWATCH_CONFORMANCE_DIR) + "/02_leader_two_hop_hex";
  auto read = read_trace(dir + "/trace.jsonl");
  ASSERT_TRUE(std::holds_alternative<Trace>(read));
  const Trace& trace = std::get<Trace>(read);
  std::string text = file_text(dir + "/watch.txt");
  while (!text.empty() && text.back() == '\n') text.pop_back();
  const std::vector<HostedWatchpoint> watches{hosted("d", text, watch::Algorithm::Distributed),
                                              hosted("c", text, watch::Algorithm::Centralized)};
  auto made = FrameReader::make(trace, read_variables(watches), default_frame_budget());
  ASSERT_TRUE(std::holds_alternative<FrameReader>(made));
  std::vector<uint64_t> found(2, 0);
  int64_t released = INT64_MIN;
  const std::vector<watch::DetectorStats> stats = replay(
      std::get<FrameReader>(made), trace.step_count(), watches,
      [&](size_t w, int64_t detected, int64_t t, std::span<const watch::ModuleId> slots,
          std::span<const watch::Value>) {
        EXPECT_EQ(detected - t, watches[w].lag()) << watches[w].watchpoint.name << " at t=" << t;
        EXPECT_GT(t, released) << "a match of a step already released";
        found[w] += slots.size() / 3;
      },
      [&](int64_t t) {
        EXPECT_GE(t, released);
        released = t;
      });
  EXPECT_EQ(released, INT64_MAX);
  ASSERT_EQ(stats.size(), 2u);
  auto lines = [&](const std::string& name) {
    std::ifstream in(dir + "/" + name);
    uint64_t n = 0;
    for (std::string line; std::getline(in, line);) n += !line.empty();
    return n;
  };
  EXPECT_EQ(found[0], lines("expected.distributed.jsonl"));
  EXPECT_EQ(found[1], lines("expected.centralized.jsonl"));
  EXPECT_GT(found[0], 0u);
  EXPECT_EQ(stats[0].matches, found[0]);
}

TEST(Replay, ReadVariablesListsEachOnceInTheOrderRead) {
  const std::vector<HostedWatchpoint> watches{
      hosted("a", "modules(a b);(a.y = 1) and (b.x = 2)", watch::Algorithm::Distributed),
      hosted("b", "modules(a);(a.x = 1) and (a.z = 0)", watch::Algorithm::Distributed)};
  EXPECT_EQ(read_variables(watches), (std::vector<std::string>{"y", "x", "z"}));
}

}  // namespace
}  // namespace dw::sim
