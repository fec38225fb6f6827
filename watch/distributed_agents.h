// The distributed watchpoint agents (paper Alg. 2), one per module: each keeps its module's
// history, starts one PatternMatcher per step, fills the next slot of every PatternMatcher that
// arrives, evaluates it, and hands clones to an outbox for delivery to its neighbours next step.
// The outbox is the seam to the messaging: an in-process transport for replay, the runtime's
// lanes in a live run.
//
// The agents of one watchpoint are held together, laid out by field rather than by module
// (AgentHistory, and the per-step truths below), so that an arriving PatternMatcher touches a
// few bytes of its receiver and nothing is allocated per module.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "watch/agent_history.h"
#include "watch/chunked_copy.h"
#include "watch/detector.h"
#include "watch/domains.h"
#include "watch/evaluator.h"
#include "watch/frame.h"
#include "watch/pattern_matcher.h"
#include "watch/program.h"

namespace dw::watch {

class PatternMatcherOutbox {
 public:
  virtual ~PatternMatcherOutbox() = default;
  // `from` sends the PatternMatcher `pm` (`bytes` long) to each neighbour in `to`, to arrive at
  // the next step. Both may be read up to kCopyChunk values past their end (see copy_ids).
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
  uint32_t slot_count;  // of the program
  uint64_t live_limit;  // the live budget; no budget is the largest number

  // Per match, the values of the program's actions (docs/design.md §4b), in step with `matches`.
  std::vector<Value> action_values;
  std::vector<std::byte> scratch;         // the PatternMatcher being filled
  EvaluatorScratch evaluation;            // value code's stacks
  std::vector<uint32_t> neighbors, rows;  // an aggregate's neighbours, or its table's rows
  VisitMarks seen;                        // within()'s and component()'s search
  std::vector<Truth> stack;
  std::vector<Truth> trial;
  std::vector<uint32_t> targets;
};

class DistributedAgents {
 public:
  // The agents of modules [first, first + modules): all of them, or a rank's own (docs/design.md §12).
  DistributedAgents(const Program& program, bool temporal_spans, uint32_t first, uint32_t modules);

  // The universe's ids (Universe::module_ids), for a program that reads id(m) (docs/design.md §4c);
  // without them each module's id is its index.
  void set_module_ids(std::vector<ModuleId> ids) { ids_ = std::move(ids); }

  uint32_t size() const { return history_.modules(); }
  const AgentHistory& history() const { return history_; }
  AgentHistory& history() { return history_; }
  // Heap bytes held.
  size_t bytes() const { return history_.bytes() + own_.capacity(); }

  // Makes room for the frame's step: once per step, before record (see AgentHistory).
  void begin_record(const Frame& frame) { history_.begin_record(frame); }
  // Modules [begin, end) record their state at frame.step. Then, at detector step
  // f = frame.step - E+ (the agents run E+ behind, to read `next`), each present one decides its
  // own leaves while its history is in cache.
  void record(const Frame& frame, uint32_t begin, uint32_t end, const Program& program, std::span<const int> columns);
  // record in two halves, for a host that lets every module record a step before any decides it
  // (a program reading the step's snapshot, reads_step_snapshot): the history first, then, once
  // every module's is, what the agents work out from it at frame step `step`.
  void record_history(const Frame& frame, uint32_t begin, uint32_t end, std::span<const int> columns) {
    history_.record(frame, begin, end, columns);
  }
  void work_out(const Program& program, int64_t step, uint32_t begin, uint32_t end);

  // What record does once the history holds detector step f: decides the own leaves of modules
  // [begin, end) at f. For a host that runs a step without a new frame (a drain at the end).
  void prepare(const Program& program, int64_t f, uint32_t begin, uint32_t end);
  // Fetches what a PatternMatcher arriving at m will read, ahead of time.
  void prefetch(uint32_t m) const { __builtin_prefetch(own_.data() + size_t{m - first_} * stride_); }
  // Detector step f: a fresh PatternMatcher with module m in its first slot.
  void start(uint32_t m, int64_t f, AgentContext& ctx, PatternMatcherOutbox& out);
  // Detector step f: a PatternMatcher sent by a neighbour at f - 1 arrives at the modules `to`,
  // in their order. It is read where it lies, and copied to be filled.
  void receive(std::span<const uint32_t> to, int64_t f, const std::byte* pm, AgentContext& ctx,
               PatternMatcherOutbox& out);

 private:
  // A conjunction with an own leaf false at m ends when m fills `slot`, whatever it carries
  // (early termination): there is nothing to fill or send.
  bool ends_here(uint32_t m, uint32_t slot, const AgentContext& ctx) const {
    return ctx.program.shape == Program::Shape::Conjunction && ctx.optimizations.early_termination &&
           own_[size_t{m - first_} * stride_ + slot] == kFalse;
  }
  void fill_and_spread(uint32_t m, int64_t f, PatternMatcherRef pm, AgentContext& ctx, PatternMatcherOutbox& out);
  void finish(uint32_t m, int64_t f, PatternMatcherRef pm, AgentContext& ctx) const;
  void act(uint32_t m, int64_t f, const PatternMatcherRef& pm, AgentContext& ctx) const;
  void finish_all(std::span<const uint32_t> to, int64_t f, const uint8_t* present, PatternMatcherRef pm,
                  AgentContext& ctx) const;
  class Reader;
  void decide_own(const Leaf& leaf, int64_t f, uint32_t begin, uint32_t end, uint32_t at);
  void work_out_kept_windows(const Program& p, int64_t newest, uint32_t begin, uint32_t end);
  void decide_own_expression(const Program& p, const Leaf& leaf, int64_t f, uint32_t begin, uint32_t end, uint32_t at);
  bool write_table(uint32_t m, int64_t f, const AggregateCode& a, AgentContext& ctx, PatternMatcherRef& pm) const;
  Truth decide(const Leaf& leaf, uint32_t m, int64_t f, const PatternMatcherRef& pm, AgentContext& ctx) const;
  Truth decide_leaves(const SlotProgram& sp, uint32_t slot, uint32_t m, int64_t f, PatternMatcherRef& pm, Truth* leaves,
                      AgentContext& ctx) const;
  bool culled(uint32_t candidate, const PatternMatcherRef& pm, AgentContext& ctx) const;

  // The own leaves (SlotProgram::own_leaves) of every present module, decided once per detector
  // step when it records: the same for every PatternMatcher it fills then. For a conjunction,
  // one truth per slot (the and of that slot's own leaves); otherwise one per leaf.
  // Module m's value of a program variable at `step`, or of kIdVariable its id; false when unknown.
  bool read_value(uint32_t m, int variable, int64_t step, int64_t& out) const {
    if (variable != kIdVariable) return history_.value(m, variable, step, out);
    if (!history_.present(m, step)) return false;
    out = ids_.empty() ? m : ids_[m];
    return true;
  }

  uint32_t stride_;
  uint32_t first_;          // the first module's id
  std::vector<Truth> own_;  // [(module - first_) * stride_ + slot or leaf]
  AgentHistory history_;
  std::vector<ModuleId> ids_;  // see set_module_ids
  // within()'s balls around each module deciding its own leaves [aggregate], roots from first_:
  // each written only by the thread that records the module's block. Kept here, beside the history
  // whose graph versions they are keyed by, so that a copy of the agents (a session's keyframe)
  // copies both; a ball around a module a PatternMatcher carries is searched each time.
  std::vector<BallCache> own_balls_;
};

}  // namespace dw::watch
