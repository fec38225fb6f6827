#include "sim/replay.h"

#include <algorithm>
#include <cstdio>
#include <memory>

#include "watch/make_detector.h"

namespace dw::sim {

std::vector<std::string> read_variables(std::span<const HostedWatchpoint> watches) {
  std::vector<std::string> out;
  for (const HostedWatchpoint& h : watches)
    for (const std::string& v : h.watchpoint.program.variables)
      if (std::find(out.begin(), out.end(), v) == out.end()) out.push_back(v);
  return out;
}

std::string replay_work_problem(const Trace& trace, uint64_t max_module_steps) {
  const uint64_t modules = trace.universe().module_count(), steps = static_cast<uint64_t>(trace.step_count());
  const uint64_t allowed =
      max_module_steps > 0 ? max_module_steps : std::max(kMinModuleSteps, kModuleStepsPerLine * trace.line_count());
  if (modules == 0 || steps <= allowed / modules) return "";
  char text[320];
  std::snprintf(text, sizeof text,
                "its %llu steps of %llu modules are %.3g module-steps to detect over (about 10 ns each), more than "
                "the %.3g allowed%s",
                static_cast<unsigned long long>(steps), static_cast<unsigned long long>(modules),
                double(steps) * double(modules), double(allowed),
                max_module_steps > 0
                    ? ""
                    : " for a trace of this many lines (1,000 a line, at least 10^9): its steps are mostly empty");
  return text;
}

std::vector<watch::DetectorStats> replay(FrameReader& frames, int64_t step_count,
                                         std::span<const HostedWatchpoint> watches, const ReplaySink& sink,
                                         const std::function<void(int64_t t)>& release, bool drain) {
  int64_t observing = 0;  // the step the detectors are given: what a match found now was detected at
  std::vector<std::unique_ptr<watch::Detector>> detectors;
  int64_t max_lag = 0;
  for (size_t i = 0; i < watches.size(); ++i) {
    watch::MatchSink each = [&sink, &observing, i](int64_t t, std::span<const watch::ModuleId> slots,
                                                   std::span<const watch::Value> actions) {
      sink(i, observing, t, slots, actions);
    };
    detectors.push_back(watch::make_detector(watches[i].algorithm, watches[i].watchpoint, frames.universe(),
                                             watches[i].options, std::move(each)));
    max_lag = std::max(max_lag, detectors.back()->lag());
  }
  for (; observing < step_count; ++observing) {
    const watch::Frame frame = frames.frame(observing);
    for (auto& d : detectors) d->observe(frame);
    if (release) release(observing - max_lag);
  }
  observing = std::max<int64_t>(step_count - 1, 0);
  if (drain)
    for (auto& d : detectors) d->finish();  // a simultaneous-state detector drains
  if (release) release(INT64_MAX);
  std::vector<watch::DetectorStats> stats;
  for (auto& d : detectors) stats.push_back(d->stats());
  return stats;
}

}  // namespace dw::sim
