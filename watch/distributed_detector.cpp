#include "watch/distributed_detector.h"

#include <chrono>

namespace dw::watch {

DistributedDetector::DistributedDetector(const Watchpoint& w, const Universe& u, DetectorOptions options,
                                         MatchSink sink)
    : Detector(u, std::move(sink)),
      program_(w.program),
      options_(options),
      columns_(variable_columns(w.program, u)),
      ctx_(w.program, options.optimizations, options.live_budget) {
  agents_.reserve(u.module_count());
  for (uint32_t m = 0; m < u.module_count(); ++m)
    agents_.emplace_back(m, program_, options.optimizations.temporal_spans);
  row_values_.resize(columns_.size());
  row_has_.resize(columns_.size());
}

size_t DistributedDetector::bytes() const {
  size_t n = agents_.capacity() * sizeof(DistributedAgent);
  for (const DistributedAgent& a : agents_) n += a.history().bytes();
  return n;
}

void DistributedDetector::observe(const Frame& frame) {
  if (stats_.stopped) return;
  const auto started = std::chrono::steady_clock::now();

  // Each agent records its own state: only the variables the watchpoint reads.
  for (uint32_t m = 0; m < agents_.size(); ++m) {
    const bool present = frame.present[m] != 0;
    if (present) {
      const size_t row = static_cast<size_t>(m) * frame.variable_count;
      for (size_t v = 0; v < columns_.size(); ++v) {
        const int c = columns_[v];
        row_has_[v] = c >= 0 && frame.has_value[row + c];
        row_values_[v] = row_has_[v] ? frame.values[row + c] : 0;
      }
    }
    agents_[m].history().record(frame.step, present, row_values_.data(), row_has_.data(),
                                present ? frame.neighbors(m) : std::span<const uint32_t>{});
  }

  // The detectors run E+ steps behind the frames, so that `next` can be read (DESIGN §4).
  const int64_t f = frame.step - program_.extent_plus;
  if (f < 0) return;
  ctx_.step = StepStats{};
  ctx_.step.step = f;
  ctx_.step.live_by_filled.assign(static_cast<size_t>(program_.slot_count()) + 1, 0);
  ctx_.match_values = 0;

  transport_.deliver();
  transport_.for_each_delivered(
      [&](uint32_t to, std::byte* pm) {
        if (!ctx_.over_budget) agents_[to].receive(f, pm, ctx_, transport_);
      },
      [&](uint32_t next) { __builtin_prefetch(&agents_[next]); });
  for (uint32_t m = 0; m < agents_.size() && !ctx_.over_budget; ++m)
    if (agents_[m].history().present(f)) agents_[m].start(f, ctx_, transport_);

  ctx_.step.created += ctx_.step.messages;  // starts were counted as they happened
  ctx_.step.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (ctx_.over_budget) {
    // The step that went over the budget was cut short: none of it is reported (as in the
    // threaded runtime, where where it was cut depends on the threads).
    stats_.stopped = true;
    stats_.stop_reason = ctx_.stop_reason.empty() ? "more than " + std::to_string(options_.live_budget) +
                                                        " live PatternMatchers at detector step " + std::to_string(f)
                                                  : ctx_.stop_reason + " at detector step " + std::to_string(f);
    return;
  }
  stats_.add(ctx_.step);

  // Everything that matched now was started at t0 = f - (k - 1).
  const int64_t t0 = f - (program_.slot_count() - 1);
  if (t0 >= 0) emit(t0, {ctx_.matches.data(), ctx_.match_values});
  // Every agent records every step (absent or not), so all hold the same amount of history.
  stats_.history_values = agents_.empty() ? 0 : agents_.front().history().held() * agents_.size();
}

}  // namespace dw::watch
