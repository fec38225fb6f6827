#include "watch/ensemble_detector.h"

#include <chrono>

namespace dw::watch {

EnsembleDetector::EnsembleDetector(const Watchpoint& w, const Universe& u, Algorithm algorithm, DetectorOptions options,
                                   MatchSink sink)
    : Detector(u, std::move(sink)),
      program_(std::make_shared<const Program>(w.program)),
      algorithm_(algorithm),
      history_(*program_, u, options.optimizations.temporal_spans, 0),
      view_(*program_, u.module_count()),
      leaves_(program_->leaves.size()),
      stack_(static_cast<size_t>(program_->max_stack)) {}

void EnsembleDetector::observe(const Frame& frame) {
  const auto started = std::chrono::steady_clock::now();
  history_.record(frame);
  const int64_t t = frame.step - program_->extent_plus;
  if (t < 0) return;
  StepStats step;
  step.step = t;
  step.live_by_filled.assign(1, 0);
  view_.resolve(history_, t);
  // No leaf reads a slot: the binding is never read, only passed.
  const uint32_t no_binding[1] = {0};
  for (uint32_t l = 0; l < leaves_.size(); ++l) leaves_[l] = view_.decide(l, no_binding);
  const bool holds = program_->evaluate(leaves_.data(), stack_.data()) == kTrue;
  step.matches = holds ? 1 : 0;
  step.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  stats_.add(step);
  stats_.history_values = history_.held_values();
  if (holds) emit_row(t);
}

}  // namespace dw::watch
