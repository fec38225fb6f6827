// The distributed watchpoint agent that runs on every module (paper Alg. 2): it keeps its own
// history, starts one PatternMatcher per step, fills the next slot of every PatternMatcher that
// arrives, evaluates it, and hands clones to an outbox for delivery to its neighbours next step.
// The outbox is the seam to the messaging: an in-process transport for replay, the runtime's
// messages in a live run.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "watch/chunked_copy.h"
#include "watch/detector.h"
#include "watch/module_history.h"
#include "watch/pattern_matcher.h"
#include "watch/program.h"

namespace dw::watch {

class PatternMatcherOutbox {
 public:
  virtual ~PatternMatcherOutbox() = default;
  // `from` sends a copy of the PatternMatcher `pm` (`bytes` long) to each neighbour in `to`, to
  // arrive at the next step.
  virtual void send(uint32_t from, std::span<const uint32_t> to, const std::byte* pm, uint32_t bytes) = 0;
};

// What agents share while one detector step runs: the compiled watchpoint, scratch space, and
// where statistics and matches go. One per thread.
struct AgentContext {
  AgentContext(const Program& program, const Optimizations& optimizations, uint64_t live_budget);

  const Program& program;
  PatternMatcherLayout layout;
  Optimizations optimizations;

  StepStats step;  // this step's statistics
  // Dense ids, slot_count per match, all of watch step f - k + 1: the first match_values of
  // `matches` (grown in chunks, so that adding a match is a plain write).
  std::vector<uint32_t> matches;  // with kCopyChunk - 1 spare values at the end
  size_t match_values = 0;
  bool over_budget = false;  // the detector must stop: past the live budget, or stop_reason
  std::string stop_reason;
  uint32_t slot_appends_sets = 0;  // bit s: filling slot s appends neighbour sets
  uint64_t live_limit;             // the live budget; no budget is the largest number

  std::vector<std::byte> scratch;
  std::vector<Truth> stack;
  std::vector<Truth> trial;
  std::vector<uint32_t> targets;
};

class DistributedAgent {
 public:
  DistributedAgent(uint32_t self, const Program& program, bool temporal_spans) : self_(self) {
    history_.configure(program, temporal_spans);
  }
  // A copy (a snapshot) forgets the per-step cache, which points into the original's history.
  DistributedAgent(const DistributedAgent& other) { *this = other; }
  DistributedAgent& operator=(const DistributedAgent& other) {
    self_ = other.self_;
    history_ = other.history_;
    own_overflow_ = other.own_overflow_;
    prepared_step_ = -1;
    prepared_slots_ = 0;
    neighbors_now_ = nullptr;
    return *this;
  }
  DistributedAgent(DistributedAgent&&) = default;
  DistributedAgent& operator=(DistributedAgent&&) = default;

  ModuleHistory& history() { return history_; }
  const ModuleHistory& history() const { return history_; }

  // Decides this module's own leaves of every slot for detector step f now (they are otherwise
  // decided at first use): a host that walks the agents in module order while their history is
  // in cache saves the scattered first touches later.
  void prepare_all(int64_t f, const Program& program) {
    if (prepared_step_ != f) prepare(f, program);
    for (uint32_t slot = 0; slot < program.slots.size(); ++slot)
      if (!(prepared_slots_ & (1u << slot))) prepare_slot(f, program, slot);
  }

  // Detector step f: a fresh PatternMatcher with this module in its first slot.
  void start(int64_t f, AgentContext& ctx, PatternMatcherOutbox& out);
  // Detector step f: a PatternMatcher sent by a neighbour at f - 1 arrives. The record is the
  // agent's to fill in place; it must have room for the neighbour sets this slot appends.
  void receive(int64_t f, std::byte* pm, AgentContext& ctx, PatternMatcherOutbox& out);

 private:
  void prepare(int64_t f, const Program& program);
  void prepare_slot(int64_t f, const Program& program, uint32_t slot);
  void fill_and_forward(int64_t f, PatternMatcherRef pm, AgentContext& ctx, PatternMatcherOutbox& out);
  void fill_and_spread(int64_t f, PatternMatcherRef pm, AgentContext& ctx, PatternMatcherOutbox& out);
  Truth decide(const Leaf& leaf, int64_t f, const PatternMatcherRef* pm) const;
  Truth decide_leaves(const Program& p, const SlotProgram& sp, int64_t f, PatternMatcherRef& pm,
                      AgentContext& ctx) const;
  bool culled(uint32_t candidate, const PatternMatcherRef& pm, AgentContext& ctx) const;

  Truth own_truth(uint32_t leaf) const { return leaf < kInlineLeaves ? own_inline_[leaf] : own_overflow_[leaf]; }

  // Hot fields first: they are what every arriving PatternMatcher touches.
  // Decided once per step (see SlotProgram::own_leaves): the step they are for, which slots' own
  // leaves are decided, N(self, f), and the truth of every own leaf (inline for the first
  // kInlineLeaves leaves).
  static constexpr uint32_t kInlineLeaves = 16;
  int64_t prepared_step_ = -1;
  uint32_t prepared_slots_ = 0;  // bit s: own leaves of slot s are decided for prepared_step_
  const std::vector<uint32_t>* neighbors_now_ = nullptr;
  std::array<Truth, kInlineLeaves> own_inline_{};
  uint32_t self_;
  std::vector<Truth> own_overflow_;
  ModuleHistory history_;
};

}  // namespace dw::watch
