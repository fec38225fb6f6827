// One step of the distributed algorithm (paper Alg. 2, docs/design.md §4) over a run of agents, as both
// of its hosts run it: the runtime, block by block on its threads (sim/watch_hosting.cpp), and the
// replay detector, every module as one block (distributed_detector.cpp). One driver, so that the
// two cannot drift apart.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "watch/distributed_agents.h"
#include "watch/frame.h"
#include "watch/record_buffer.h"

namespace dw::watch {

// Detector step f for agents [begin, end): the PatternMatchers sent to them during f - 1 (in the
// `arriving` lanes) are received, then every present agent starts its own. Stops as soon as the
// context is over its budget.
void step_agents(DistributedAgents& agents, uint32_t begin, uint32_t end, int64_t f,
                 std::span<RecordBuffer* const> arriving, AgentContext& ctx, PatternMatcherOutbox& out);

// Makes a context ready for detector step f.
void start_agent_step(AgentContext& ctx, int64_t f);

// The step's outcome, summed over the contexts that ran it (one per thread).
struct AgentStepOutcome {
  StepStats stats;
  bool over_budget = false;  // the step is cut short: it reports nothing, the watchpoint stops
  std::string stop_reason;
};
AgentStepOutcome finish_agent_step(std::span<AgentContext* const> contexts, int64_t f, uint64_t live_budget);
// finish_agent_step in two parts, for hosts that add up outcomes of their own first (the ranks of
// a run): the contexts' sum, and the budget's verdict on a sum.
AgentStepOutcome sum_agent_step(std::span<AgentContext* const> contexts, int64_t f);
void decide_agent_budget(AgentStepOutcome& outcome, int64_t f, uint64_t live_budget);

}  // namespace dw::watch
