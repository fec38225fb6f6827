// The distributed watchpoint agent that runs on every module (paper Alg. 2): it keeps its own
// history, starts one PatternMatcher per step, fills the next slot of every PatternMatcher that
// arrives, evaluates it, and hands clones to an outbox for delivery to its neighbours next step.
// The outbox is the seam to the messaging: an in-process transport for replay, the runtime's
// messages in a live run.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "watch/detector.h"
#include "watch/module_history.h"
#include "watch/pattern_matcher.h"
#include "watch/program.h"

namespace dw::watch {

class PatternMatcherOutbox {
 public:
  virtual ~PatternMatcherOutbox() = default;
  // Room for a PatternMatcher of `bytes` bytes that `from` sends to its neighbour `to`, to arrive
  // at the next step. The caller writes the record there before the next call.
  virtual std::byte* reserve(uint32_t from, uint32_t to, uint32_t bytes) = 0;
};

// What agents share while one detector step runs: the compiled watchpoint, scratch space, and
// where statistics and matches go. One per thread.
struct AgentContext {
  AgentContext(const Program& program, const Optimizations& optimizations, uint64_t live_budget);

  const Program& program;
  PatternMatcherLayout layout;
  Optimizations optimizations;
  uint64_t live_budget;  // 0: none

  StepStats step;                // this step's statistics
  std::vector<uint32_t> matches; // dense ids, slot_count per match, all of watch step f - k + 1
  bool over_budget = false;

  std::vector<std::byte> scratch;
  std::vector<Truth> stack;
  std::vector<Truth> trial;
};

class DistributedAgent {
 public:
  DistributedAgent(uint32_t self, const Program& program, bool temporal_spans) : self_(self) {
    history_.configure(program, temporal_spans);
  }

  ModuleHistory& history() { return history_; }
  const ModuleHistory& history() const { return history_; }

  // Detector step f: a fresh PatternMatcher with this module in its first slot.
  void start(int64_t f, AgentContext& ctx, PatternMatcherOutbox& out);
  // Detector step f: a PatternMatcher sent by a neighbour at f - 1 arrives.
  void receive(int64_t f, const std::byte* pm, AgentContext& ctx, PatternMatcherOutbox& out);

 private:
  void fill_and_forward(int64_t f, PatternMatcherRef pm, AgentContext& ctx, PatternMatcherOutbox& out);
  Truth decide(const Leaf& leaf, int64_t f, const PatternMatcherRef& pm) const;
  bool culled(uint32_t candidate, const PatternMatcherRef& pm, AgentContext& ctx) const;

  uint32_t self_;
  ModuleHistory history_;
};

}  // namespace dw::watch
