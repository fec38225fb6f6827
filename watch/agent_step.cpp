#include "watch/agent_step.h"

namespace dw::watch {

RunBudget::RunBudget(uint64_t limit, std::vector<uint64_t> own)
    : limit_(limit), own_(std::move(own)), counted_(std::make_unique<std::atomic<uint64_t>[]>(own_.size())) {}

void RunBudget::begin_step(std::optional<uint64_t> before, uint32_t from) {
  before_ = before;
  from_ = from;
  for (size_t i = 0; i < own_.size(); ++i) counted_[i].store(0, std::memory_order_relaxed);
}

void RunBudget::charge_context(uint32_t order, AgentContext& ctx, uint64_t& published) {
  if (limit_ == 0) return;
  const uint64_t used = ctx.step.live + ctx.step.messages;
  if (used > published) {
    counted_[order].fetch_add(used - published, std::memory_order_relaxed);
    published = used;
  }
  // What the watchpoints up to this one have charged so far, this context's count included: a
  // lower bound of what they will be charged, so that a context held back at the room left
  // proves the step passes the budget (it wanted one more).
  const bool after_before = before_ && order >= from_;
  uint64_t total = after_before ? *before_ : 0;
  for (uint32_t i = after_before ? from_ : 0; i <= order; ++i)
    total += charge(counted_[i].load(std::memory_order_relaxed), own_[i]);
  const uint64_t room = limit_ > total ? limit_ - total : 0;
  ctx.live_limit = std::min(own_[order] == 0 ? UINT64_MAX : own_[order], used + room);
}

void step_agents(DistributedAgents& agents, uint32_t begin, uint32_t end, int64_t f,
                 std::span<RecordBuffer* const> arriving, AgentContext& ctx, PatternMatcherOutbox& out, RunCharge run) {
  // The run's budget is charged every kChargeEvery PatternMatchers and messages (and once a call):
  // a context held back between two charges only uses less than the room it was given.
  constexpr uint64_t kChargeEvery = 4096;
  uint64_t next_charge = 0;
  const auto charge = [&] {
    if (run.budget == nullptr) return;
    const uint64_t used = ctx.step.live + ctx.step.messages;
    if (used < next_charge) return;
    run.budget->charge_context(run.order, ctx, *run.published);
    next_charge = used + kChargeEvery;
  };
  for (RecordBuffer* lane : arriving)
    lane->for_each(
        [&](std::span<const uint32_t> to, const std::byte* pm) {
          if (ctx.over_budget) return;
          charge();
          agents.receive(to, f, pm, ctx, out);
        },
        [&](uint32_t next) { agents.prefetch(next); });
  const uint8_t* present = agents.history().presence(f);  // from the history's first module on
  const uint32_t first = agents.history().first();
  if (ctx.program.aggregate_hops > 0)  // each brought its neighbours' values, one message each
    for (uint32_t m = begin; m < end; ++m) {
      uint32_t degree = 0;
      if (present[m - first] && agents.history().neighbors(m, f, degree) != nullptr) ctx.step.value_messages += degree;
    }
  for (uint32_t m = begin; m < end && !ctx.over_budget; ++m)
    if (present[m - first]) {
      charge();
      agents.start(m, f, ctx, out);
    }
  if (run.budget != nullptr) run.budget->charge_context(run.order, ctx, *run.published);
}

void start_agent_step(AgentContext& ctx, int64_t f) {
  ctx.step = StepStats{};
  ctx.step.step = f;
  ctx.step.live_by_filled.assign(static_cast<size_t>(ctx.program.slot_count()) + 1, 0);
  ctx.match_values = 0;
  ctx.action_values.clear();
  // A budget stop belongs to the step that hit it: a run rolled back to before that step and
  // resumed must start clean, as the straight run did (the stop itself is the host's state).
  ctx.over_budget = false;
  ctx.stop_reason.clear();
}

AgentStepOutcome finish_agent_step(std::span<AgentContext* const> contexts, int64_t f, uint64_t live_budget) {
  AgentStepOutcome o = sum_agent_step(contexts, f);
  decide_agent_budget(o, f, live_budget);
  return o;
}

AgentStepOutcome sum_agent_step(std::span<AgentContext* const> contexts, int64_t f) {
  AgentStepOutcome o;
  o.stats.step = f;
  const size_t k = contexts.empty() ? 0 : static_cast<size_t>(contexts.front()->program.slot_count());
  o.stats.live_by_filled.assign(k + 1, 0);
  for (AgentContext* ctx : contexts) {
    ctx->step.created += ctx->step.messages;  // starts were counted as they happened
    const StepStats& st = ctx->step;
    for (size_t i = 0; i < st.live_by_filled.size(); ++i) o.stats.live_by_filled[i] += st.live_by_filled[i];
    o.stats.live += st.live;
    o.stats.created += st.created;
    o.stats.messages += st.messages;
    o.stats.bytes += st.bytes;
    o.stats.matches += st.matches;
    o.stats.value_messages += st.value_messages;
    o.wanted += st.live + st.messages + (ctx->over_budget ? 1 : 0);
    o.held_back = o.held_back || ctx->over_budget;
    if (ctx->over_budget && !o.over_budget) {
      o.over_budget = true;
      o.stop_reason = ctx->stop_reason;
    }
  }
  return o;
}

void decide_agent_budget(AgentStepOutcome& o, int64_t f, uint64_t live_budget) {
  // Each context may use the whole budget; whether the step went over it is decided on their sum,
  // so that the stop never depends on how many threads (or ranks) ran the step.
  if (live_budget != 0 && o.stats.live + o.stats.messages > live_budget) o.over_budget = true;
  if (o.over_budget)
    o.stop_reason = o.stop_reason.empty() ? "more than " + std::to_string(live_budget) +
                                                " live PatternMatchers at detector step " + std::to_string(f)
                                          : o.stop_reason + " at detector step " + std::to_string(f);
}

}  // namespace dw::watch
