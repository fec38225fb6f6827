#include "watch/centralized_detector.h"

#include <chrono>

namespace dw::watch {

CentralizedDetector::CentralizedDetector(const Watchpoint& w, const Universe& u, DetectorOptions options,
                                         MatchSink sink)
    : Detector(u, std::move(sink)),
      program_(std::make_shared<const Program>(w.program)),
      options_(options),
      shape_(group_shape(Algorithm::Centralized, options)),
      history_(*program_, u, options.optimizations.temporal_spans, 0),
      view_(*program_, u.module_count()),
      search_(*program_, options.optimizations, options.live_budget, u.module_count()),
      groups_(u.module_count()),
      eligible_(u.module_count(), 0) {}

size_t CentralizedDetector::bytes() const {
  return sizeof(*this) + history_.bytes() + view_.bytes() + matches_.ids.capacity() * sizeof(uint32_t);
}

void CentralizedDetector::observe(const Frame& frame) {
  if (stats_.stopped) return;
  const auto started = std::chrono::steady_clock::now();
  history_.record(frame);
  const int64_t t = frame.step - program_->extent_plus;
  if (t < 0) return;
  step_ = StepStats{};
  step_.step = t;
  step_.live_by_filled.assign(static_cast<size_t>(program_->slot_count()) + 1, 0);
  matches_.values = 0;
  run_step(t);
  // The step that went over the budget was cut short: none of it is reported (as distributed).
  if (search_.stopped()) {
    stats_.stopped = true;
    stats_.stop_reason = search_.stop_reason();
    return;
  }
  step_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  stats_.add(step_);
  stats_.history_values = history_.held_values();
  action_values(view_, *program_, {matches_.ids.data(), matches_.values}, actions_);
  emit(t, {matches_.ids.data(), matches_.values}, actions_);
}

void CentralizedDetector::run_step(int64_t t) {
  view_.resolve(history_, t, shape_ == GroupShape::Any);
  const StepHistory::Graph& now = *view_.now();
  const uint32_t modules = universe_.module_count();
  if (shape_ != GroupShape::Any) {
    first_.clear();
    for (uint32_t m = 0; m < modules; ++m)
      if (now.present[m]) first_.push_back(m);
    search_.search(view_, shape_, first_, step_, matches_);
    return;
  }
  // Any: each connected group once, then its slot assignments. With early termination a module
  // that can fill no slot (its own leaves make the expression false in each) is in no match, so
  // the groups are those of the graph without it.
  for (uint32_t m = 0; m < modules; ++m)
    eligible_[m] = now.present[m] && (!options_.optimizations.early_termination || view_.fillable(m) != 0);
  // The groups grown, whole or partial, are held to the live budget as the bindings are: each is
  // what a PatternMatcher growing that group would be.
  const uint64_t budget = options_.live_budget;
  const bool whole = groups_.enumerate(
      now, eligible_, static_cast<uint32_t>(program_->slot_count()),
      [&](std::span<const uint32_t> group) {
        search_.assign(view_, group, step_, matches_);
        return !search_.stopped();
      },
      budget);
  if (!whole && !search_.stopped())
    search_.stop("more than " + std::to_string(budget) + " connected groups grown at watch step " + std::to_string(t) +
                 " (whole or partial)");
}

}  // namespace dw::watch
