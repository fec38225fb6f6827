#include "watch/distributed_detector.h"

#include <chrono>

#include "watch/agent_step.h"

namespace dw::watch {

DistributedDetector::DistributedDetector(const Watchpoint& w, const Universe& u, DetectorOptions options,
                                         MatchSink sink)
    : Detector(u, std::move(sink)),
      program_(w.program),
      options_(options),
      columns_(variable_columns(w.program, u)),
      agents_(w.program, options.optimizations.temporal_spans, 0, u.module_count()),
      ctx_(w.program, options.optimizations, options.live_budget) {
  if (w.program.reads_id) agents_.set_module_ids(u.module_ids);
}

size_t DistributedDetector::bytes() const { return sizeof(DistributedAgents) + agents_.bytes(); }

void DistributedDetector::observe(const Frame& frame) {
  if (stats_.stopped) return;
  agents_.begin_record(frame);
  agents_.record(frame, 0, agents_.size(), program_, columns_);
  newest_ = frame.step;
  const int64_t f = frame.step - program_.agent_delay();
  if (f >= 0) run_step(f);
}

void DistributedDetector::finish() {
  while (!stats_.stopped && next_f_ <= newest_ - program_.extent_plus) {
    agents_.prepare(program_, next_f_, 0, agents_.size());
    run_step(next_f_);
  }
}

void DistributedDetector::run_step(int64_t f) {
  const auto started = std::chrono::steady_clock::now();
  next_f_ = f + 1;
  start_agent_step(ctx_, f);
  transport_.deliver();
  RecordBuffer* arriving[] = {&transport_.delivered()};
  step_agents(agents_, 0, agents_.size(), f, arriving, ctx_, transport_);
  AgentContext* contexts[] = {&ctx_};
  AgentStepOutcome outcome = finish_agent_step(contexts, f, options_.live_budget);
  outcome.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (outcome.over_budget) {
    stats_.stopped = true;
    stats_.stop_reason = std::move(outcome.stop_reason);
    return;
  }
  stats_.add(outcome.stats);
  // Everything that matched now was started at t0 = f - (k - 1).
  const int64_t t0 = f - (program_.slot_count() - 1);
  if (t0 >= 0) emit(t0, {ctx_.matches.data(), ctx_.match_values}, ctx_.action_values);
  stats_.history_values = agents_.history().held();
}

}  // namespace dw::watch
