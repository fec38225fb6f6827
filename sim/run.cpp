#include "sim/run.h"

#include <algorithm>

namespace dw::sim {

Run::Run(const Model& model, World& world, RunOptions options)
    : runtime_(model, world, options.threads), options_(options), state_(runtime_.initial_state()) {
  matches_.resize(model.watches.size());
  stats_.resize(model.watches.size());
  stats_step_.resize(model.watches.size());
  take_snapshot();
}

void Run::take_snapshot() {
  if (options_.snapshots == 0) return;
  // The ring holds the state before step 0 as well as the states after the last K steps.
  const size_t capacity = options_.snapshots + 1;
  if (ring_.size() < capacity) {
    ring_.push_back(state_);
    return;
  }
  // Full: overwrite the oldest, reusing its memory.
  ring_[ring_start_] = state_;
  ring_start_ = (ring_start_ + 1) % capacity;
}

std::optional<int64_t> Run::oldest_snapshot() const {
  if (ring_.empty()) return std::nullopt;
  return ring_[ring_start_].step - 1;
}

void Run::record(const StepOutput& out) {
  for (uint32_t w = 0; w < out.watches.size(); ++w) {
    const WatchStepOutput& o = out.watches[w];
    if (o.observed) {
      stats_[w].add(o.stats);
      stats_step_[w].push_back(out.step);
    }
    if (o.slots.empty()) continue;
    const uint32_t k = model().watches[w].watchpoint.program.slot_count();
    MatchList& list = matches_[w];
    list.slots.insert(list.slots.end(), o.slots.begin(), o.slots.end());
    list.t.insert(list.t.end(), o.slots.size() / k, o.t);
    list.detected.insert(list.detected.end(), o.slots.size() / k, out.step);
  }
  for (uint32_t w = 0; w < state_.watches.size(); ++w) {
    stats_[w].stopped = state_.watches[w].stopped;
    stats_[w].stop_reason = state_.watches[w].stop_reason;
  }
}

std::optional<Pause> Run::run_until(int64_t end, const StepObserver& observer) {
  while (state_.step < end) {
    runtime_.step(state_, out_);
    record(out_);
    take_snapshot();
    if (observer) observer(state_, out_);
    for (uint32_t w = 0; w < out_.watches.size(); ++w) {
      const WatchStepOutput& o = out_.watches[w];
      if (model().watches[w].action != MatchAction::Pause || o.matches == 0 || out_.step <= pause_guard_) continue;
      pause_guard_ = out_.step;
      const uint32_t k = model().watches[w].watchpoint.program.slot_count();
      return Pause{w, o.t, out_.step, {o.slots.begin(), o.slots.begin() + k}, o.matches};
    }
  }
  return std::nullopt;
}

bool Run::rollback_to(int64_t t) {
  if (ring_.empty()) return false;
  const int64_t oldest = ring_[ring_start_].step - 1;
  const int64_t newest = oldest + static_cast<int64_t>(ring_.size()) - 1;
  if (t < oldest || t > newest) return false;
  const size_t back = static_cast<size_t>(t - oldest);
  state_ = ring_[(ring_start_ + back) % ring_.size()];
  // Snapshots after t describe a future that is gone.
  if (back + 1 < ring_.size()) {
    std::vector<State> kept;
    for (size_t i = 0; i <= back; ++i) kept.push_back(std::move(ring_[(ring_start_ + i) % ring_.size()]));
    ring_ = std::move(kept);
    ring_start_ = 0;
  }
  for (uint32_t w = 0; w < matches_.size(); ++w) {
    MatchList& list = matches_[w];
    const size_t keep =
        static_cast<size_t>(std::upper_bound(list.detected.begin(), list.detected.end(), t) - list.detected.begin());
    const uint32_t k = model().watches[w].watchpoint.program.slot_count();
    list.t.resize(keep);
    list.detected.resize(keep);
    list.slots.resize(keep * k);
    // The statistics are rebuilt from the series that is kept.
    std::vector<int64_t>& at = stats_step_[w];
    const size_t entries = static_cast<size_t>(std::upper_bound(at.begin(), at.end(), t) - at.begin());
    std::vector<watch::StepStats> series(
        stats_[w].steps.begin(),
        stats_[w].steps.begin() + static_cast<ptrdiff_t>(std::min(entries, stats_[w].steps.size())));
    at.resize(entries);
    stats_[w] = watch::DetectorStats{};
    for (const watch::StepStats& s : series) stats_[w].add(s);
    stats_[w].stopped = state_.watches[w].stopped;
    stats_[w].stop_reason = state_.watches[w].stop_reason;
  }
  runtime_.world().restore(model(), state_);
  return true;
}

}  // namespace dw::sim
