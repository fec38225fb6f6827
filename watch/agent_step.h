// One step of the distributed algorithm (paper Alg. 2, docs/design.md §4) over a run of agents, as both
// of its hosts run it: the runtime, block by block on its threads (sim/watch_hosting.cpp), and the
// replay detector, every module as one block (distributed_detector.cpp). One driver, so that the
// two cannot drift apart.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "watch/distributed_agents.h"
#include "watch/frame.h"
#include "watch/record_buffer.h"

namespace dw::watch {

// The PatternMatcher budget of a whole run, over all its watchpoints together (docs/cli.md,
// --max-live-all), as the agents of a step charge it while they run. Each watchpoint is charged
// min(c, own + 1) for a step where it wanted c live PatternMatchers and messages and its own budget
// is `own` (none: c), in the run's charging order; the first watchpoint whose running total passes
// the budget stops, and so does every one after it that ran the step. The host decides that on
// the step's sums; while the step runs, a context is held back (its live_limit lowered) only once
// what the watchpoints up to its own have charged so far proves the total will pass the budget,
// so that the stop never depends on threads, ranks or timing, and a step's PatternMatchers over
// all watchpoints stay within about the budget.
class RunBudget {
 public:
  // `limit` 0: no budget of the run. `own[i]` is the budget of the watchpoint charged i-th (0: none).
  RunBudget(uint64_t limit, std::vector<uint64_t> own);
  uint64_t limit() const { return limit_; }
  // What a watchpoint whose own budget is `own` is charged for wanting `wanted`.
  static uint64_t charge(uint64_t wanted, uint64_t own) { return own == 0 ? wanted : std::min(wanted, own + 1); }
  // A new step. With `before`, the watchpoints charged from `from` on are charged after it instead
  // of after those charged before them (a session stepping some alone: what the run was charged
  // at that step holds the others').
  void begin_step(std::optional<uint64_t> before = std::nullopt, uint32_t from = 0);
  // The context of the watchpoint charged `order`-th, `published` of whose count it has charged
  // so far: charges the rest and lowers its live_limit to what the run has room for. Any thread.
  void charge_context(uint32_t order, AgentContext& ctx, uint64_t& published);
  // A context's own budget (its live_limit at the start of a step).
  uint64_t own(uint32_t order) const { return own_[order]; }

 private:
  uint64_t limit_;
  std::vector<uint64_t> own_;
  std::optional<uint64_t> before_;
  uint32_t from_ = 0;
  std::unique_ptr<std::atomic<uint64_t>[]> counted_;  // by charging order: what its contexts charged this step
};

// Detector step f for agents [begin, end): the PatternMatchers sent to them during f - 1 (in the
// `arriving` lanes) are received, then every present agent starts its own. Stops as soon as the
// context is over its budget. With `run`, the context charges the whole run's budget as it goes
// (RunBudget::charge_context: the watchpoint charged `order`-th; `published`, the context's own
// running tally for the step).
struct RunCharge {
  RunBudget* budget = nullptr;
  uint32_t order = 0;
  uint64_t* published = nullptr;
};
void step_agents(DistributedAgents& agents, uint32_t begin, uint32_t end, int64_t f,
                 std::span<RecordBuffer* const> arriving, AgentContext& ctx, PatternMatcherOutbox& out,
                 RunCharge run = {});

// Makes a context ready for detector step f.
void start_agent_step(AgentContext& ctx, int64_t f);

// The step's outcome, summed over the contexts that ran it (one per thread).
struct AgentStepOutcome {
  StepStats stats;
  bool over_budget = false;  // the step is cut short: it reports nothing, the watchpoint stops
  std::string stop_reason;
  // A lower bound of the live PatternMatchers and messages the step wanted: its count, and one
  // more for each context held back (it wanted one past its limit). Exact when none was.
  uint64_t wanted = 0;
  bool held_back = false;  // some context was held back by a limit (its own or the run's)
};
AgentStepOutcome finish_agent_step(std::span<AgentContext* const> contexts, int64_t f, uint64_t live_budget);
// finish_agent_step in two parts, for hosts that add up outcomes of their own first (the ranks of
// a run): the contexts' sum, and the budget's verdict on a sum.
AgentStepOutcome sum_agent_step(std::span<AgentContext* const> contexts, int64_t f);
void decide_agent_budget(AgentStepOutcome& outcome, int64_t f, uint64_t live_budget);

}  // namespace dw::watch
