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
  // Each detector's per-step series keeps the steps where something happened, at most
  // kSeriesEntries over all of them: a trace of three lines, one at step 9,999,999, named 10^7
  // steps, and 12 watchpoints held a million entries each (3 GB).
  std::vector<std::vector<watch::StepStats>> series(detectors.size());
  size_t entries = 0;
  bool truncated = false;
  for (auto& d : detectors) d->stats().max_steps = 0;
  for (; observing < step_count; ++observing) {
    const watch::Frame frame = frames.frame(observing);
    for (size_t i = 0; i < detectors.size(); ++i) {
      watch::DetectorStats& st = detectors[i]->stats();
      const uint64_t before = st.observed_steps;
      detectors[i]->observe(frame);
      const watch::StepStats& s = st.last;
      if (st.observed_steps == before || !(s.live || s.created || s.messages || s.matches || s.lost)) continue;
      if (entries < kSeriesEntries) {
        series[i].push_back(s);
        ++entries;
      } else {
        truncated = true;
      }
    }
    if (release) release(observing - max_lag);
  }
  observing = std::max<int64_t>(step_count - 1, 0);
  if (drain)
    for (auto& d : detectors) {
      d->stats().max_steps = watch::DetectorStats::kMaxSteps;  // the drain's few steps, kept whole
      d->finish();                                             // a simultaneous-state detector drains
    }
  if (release) release(INT64_MAX);
  std::vector<watch::DetectorStats> stats;
  for (size_t i = 0; i < detectors.size(); ++i) {
    stats.push_back(detectors[i]->stats());
    // The detector's own series holds the drain's steps alone.
    series[i].insert(series[i].end(), stats.back().steps.begin(), stats.back().steps.end());
    stats.back().steps = std::move(series[i]);
    stats.back().steps_truncated = truncated;
  }
  return stats;
}

}  // namespace dw::sim
