// The run's outputs and their rules (sim/run_outputs.h): what a `count` watchpoint writes, the
// drain at a run's end, the pause line, and whether a replay drains.
#include "sim/run_outputs.h"

#include <gtest/gtest.h>

#include <sstream>
#include <stdexcept>

#include "tests/sim/test_programs.h"

namespace dw::sim {
namespace {

using test_programs::gossip_model;

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST(RunOutputs, ACountWatchpointWritesItsNumberAndTheOthersTheirMatchesThenTheRunDrains) {
  const std::string text = "modules(a b c); (a.v = 1) and (b.v = 2) and (c.mix > b.mix)";
  auto model = gossip_model({LatticeKind::Cubic, {5, 4, 3}},
                            {{text, watch::Algorithm::Distributed}, {text, watch::Algorithm::Centralized}});
  model->watches[0].watchpoint.name = "logged";
  model->watches[1].watchpoint.name = "counted";
  model->watches[1].action = MatchAction::Count;
  StaticLatticeWorld world;
  Session run(*model, world, {.threads = 1});
  std::ostringstream log;
  RunOutputs outputs(run.watches().hosted(), &log);
  const auto pause = run.run_until(30, [&](const State&, const StepOutput& out) { outputs.step(out); });
  ASSERT_FALSE(pause);
  outputs.end_run(run, pause, 30);
  EXPECT_THROW(run.run_until(31), std::logic_error) << "a run that went to its end drained";
  const std::vector<uint64_t> counts{run.match_count(0), run.match_count(1)};
  outputs.finish(counts);

  ASSERT_GT(counts[0], 0u);
  ASSERT_GT(counts[1], 0u);
  EXPECT_EQ(outputs.count(0), counts[0]);
  EXPECT_EQ(outputs.count(1), counts[1]);
  const std::vector<std::string> lines = lines_of(log.str());
  ASSERT_EQ(lines.size(), counts[0] + 1);
  for (size_t i = 0; i + 1 < lines.size(); ++i) EXPECT_EQ(lines[i].rfind("{\"watch\":\"logged\",\"t\":", 0), 0u);
  EXPECT_EQ(lines.back(), "{\"watch\":\"counted\",\"counted\":" + std::to_string(counts[1]) + "}");
}

TEST(RunOutputs, APauseEndsTheTraceWithItsLineAndItsReplayLeavesTheLastStepsUndecided) {
  auto model = gossip_model({LatticeKind::Square2d, {5, 5, 1}},
                            {{"modules(a b); (a.v = 1) and (b.v = 1)", watch::Algorithm::Distributed}});
  model->watches[0].action = MatchAction::Pause;
  StaticLatticeWorld world;
  Session run(*model, world, {.threads = 1});
  std::ostringstream trace;
  RunOutputs outputs(run.watches().hosted(), nullptr);
  outputs.record(trace, model->universe, {});
  const auto pause = run.run_until(50, [&](const State& state, const StepOutput& out) {
    const watch::Frame frame = observed_frame(*model, state, out);
    outputs.step(out, &frame);
  });
  ASSERT_TRUE(pause);
  outputs.end_run(run, pause, 50);
  outputs.finish();
  EXPECT_NO_THROW(run.run_until(run.latest() + 2)) << "a paused run did not drain";
  const std::vector<std::string> lines = lines_of(trace.str());
  EXPECT_EQ(lines.back(), "{\"paused\":{\"watch\":\"w\",\"t\":" + std::to_string(pause->t) + "}}");

  auto read = read_trace_text("t.jsonl", trace.str());
  ASSERT_TRUE(std::holds_alternative<Trace>(read)) << std::get<std::vector<TraceError>>(read)[0].format();
  EXPECT_FALSE(RunOutputs::replay_drains(std::get<Trace>(read), true)) << "its own watchpoints find what it found";
  EXPECT_TRUE(RunOutputs::replay_drains(std::get<Trace>(read), false)) << "others decide its last steps";
  auto unpaused = read_trace_text("t.jsonl", "{\"t\":0,\"m\":0,\"vars\":{},\"nbrs\":[]}\n");
  EXPECT_TRUE(RunOutputs::replay_drains(std::get<Trace>(unpaused), true));
}

}  // namespace
}  // namespace dw::sim
