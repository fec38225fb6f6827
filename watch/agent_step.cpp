#include "watch/agent_step.h"

namespace dw::watch {

void record_agents(std::span<DistributedAgent> agents, uint32_t begin, uint32_t end, const Frame& frame,
                   const Program& program, std::span<const int> columns) {
  constexpr size_t kMaxInline = 64;
  int64_t values[kMaxInline];
  uint8_t has[kMaxInline];
  std::vector<int64_t> more_values;
  std::vector<uint8_t> more_has;
  int64_t* row_values = values;
  uint8_t* row_has = has;
  if (columns.size() > kMaxInline) {
    more_values.resize(columns.size());
    more_has.resize(columns.size());
    row_values = more_values.data();
    row_has = more_has.data();
  }
  const int64_t f = frame.step - program.extent_plus;
  for (uint32_t m = begin; m < end; ++m) {
    const bool present = frame.present[m] != 0;
    const size_t row = size_t{m} * frame.variable_count;
    for (size_t v = 0; v < columns.size(); ++v) {
      const int c = columns[v];
      row_has[v] = present && c >= 0 && frame.has_value[row + size_t(c)];
      row_values[v] = row_has[v] ? frame.values[row + size_t(c)] : 0;
    }
    agents[m].history().record(frame.step, present, row_values, row_has,
                               present ? frame.neighbors(m) : std::span<const uint32_t>{});
    if (f >= 0 && agents[m].history().present(f)) agents[m].prepare_all(f, program);
  }
}

void step_agents(std::span<DistributedAgent> agents, uint32_t begin, uint32_t end, int64_t f,
                 std::span<RecordBuffer* const> arriving, AgentContext& ctx, PatternMatcherOutbox& out) {
  for (RecordBuffer* lane : arriving)
    lane->for_each(
        [&](uint32_t to, std::byte* pm) {
          if (!ctx.over_budget) agents[to].receive(f, pm, ctx, out);
        },
        [&](uint32_t next) { __builtin_prefetch(&agents[next]); });
  for (uint32_t m = begin; m < end && !ctx.over_budget; ++m)
    if (agents[m].history().present(f)) agents[m].start(f, ctx, out);
}

void start_agent_step(AgentContext& ctx, int64_t f) {
  ctx.step = StepStats{};
  ctx.step.step = f;
  ctx.step.live_by_filled.assign(static_cast<size_t>(ctx.program.slot_count()) + 1, 0);
  ctx.match_values = 0;
  // A budget stop belongs to the step that hit it: a run rolled back to before that step and
  // resumed must start clean, as the straight run did (the stop itself is the host's state).
  ctx.over_budget = false;
  ctx.stop_reason.clear();
}

AgentStepOutcome finish_agent_step(std::span<AgentContext* const> contexts, int64_t f, uint64_t live_budget) {
  AgentStepOutcome o;
  o.stats.step = f;
  const size_t k = contexts.empty() ? 0 : static_cast<size_t>(contexts.front()->program.slot_count());
  o.stats.live_by_filled.assign(k + 1, 0);
  uint64_t used = 0;
  for (AgentContext* ctx : contexts) {
    ctx->step.created += ctx->step.messages;  // starts were counted as they happened
    const StepStats& st = ctx->step;
    for (size_t i = 0; i < st.live_by_filled.size(); ++i) o.stats.live_by_filled[i] += st.live_by_filled[i];
    o.stats.live += st.live;
    o.stats.created += st.created;
    o.stats.messages += st.messages;
    o.stats.bytes += st.bytes;
    o.stats.matches += st.matches;
    used += st.live + st.messages;
    if (ctx->over_budget && !o.over_budget) {
      o.over_budget = true;
      o.stop_reason = ctx->stop_reason;
    }
  }
  // Each context may use the whole budget; whether the step went over it is decided on their sum,
  // so that the stop never depends on how many threads ran the step.
  if (live_budget != 0 && used > live_budget) o.over_budget = true;
  if (o.over_budget)
    o.stop_reason = o.stop_reason.empty() ? "more than " + std::to_string(live_budget) +
                                                " live PatternMatchers at detector step " + std::to_string(f)
                                          : o.stop_reason + " at detector step " + std::to_string(f);
  return o;
}

}  // namespace dw::watch
