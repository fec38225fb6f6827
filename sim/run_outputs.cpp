#include "sim/run_outputs.h"

#include <algorithm>

namespace dw::sim {
namespace {

std::vector<MatchLog::WatchInfo> infos(const HostedWatches& watches) {
  std::vector<MatchLog::WatchInfo> out;
  for (const HostedWatchpoint& h : watches) out.push_back(MatchLog::info(h.watchpoint));
  return out;
}

}  // namespace

RunOutputs::RunOutputs(const HostedWatches& watches, std::ostream* matches, size_t keep)
    : watches_(watches), log_(infos(watches), matches, keep), counted_(watches.size(), 0) {
  for (uint32_t w = 0; w < watches_.size(); ++w) {
    sinks_.push_back(log_.sink(w));
    max_lag_ = std::max(max_lag_, watches_[w].lag());
  }
}

void RunOutputs::record(std::ostream& out, const watch::Universe& universe,
                        std::span<const Intervention> interventions) {
  trace_ = std::make_unique<TraceWriter>(out, universe, interventions, specs_of(watches_));
}

void RunOutputs::found(uint32_t w, int64_t t, uint64_t matches, std::span<const ModuleId> slots,
                       std::span<const watch::Value> actions) {
  if (!lists_matches(watches_[w].action)) counted_[w] += matches;
  else if (matches > 0) sinks_[w](t, slots, actions);
}

void RunOutputs::step(const StepOutput& out, const watch::Frame* frame) {
  if (frame) record_frame(*frame);
  for (uint32_t w = 0; w < out.watches.size(); ++w) {
    const WatchStepOutput& o = out.watches[w];
    found(w, o.t, o.matches, o.slots, o.actions);
  }
  release(out.step - max_lag_);
}

void RunOutputs::end_run(Session& session, const std::optional<Pause>& pause, int64_t steps) {
  if (pause) {
    if (trace_) trace_->write_paused({session.watches()[pause->watch].hosted.watchpoint.name, pause->t});
    return;
  }
  if (session.latest() + 1 < steps) return;
  session.drain([&](uint32_t w, int64_t t, std::span<const ModuleId> ids, std::span<const watch::Value> actions) {
    found(w, t, watch::match_rows(ids.size(), watches_[w].watchpoint.program.slot_count()), ids, actions);
  });
}

bool RunOutputs::replay_drains(const Trace& trace, bool own_watchpoints) { return !own_watchpoints || !trace.paused(); }

void RunOutputs::finish(std::span<const uint64_t> counted) {
  log_.finish();
  for (uint32_t w = 0; w < watches_.size(); ++w)
    if (!lists_matches(watches_[w].action))
      log_.write_counted(watches_[w].watchpoint.name, counted.empty() ? counted_[w] : counted[w]);
}

uint64_t RunOutputs::count(uint32_t w) const { return lists_matches(watches_[w].action) ? log_.count(w) : counted_[w]; }

}  // namespace dw::sim
