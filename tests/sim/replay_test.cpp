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
