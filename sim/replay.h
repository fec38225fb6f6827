// Watchpoints over a recorded trace (docs/design.md §5): one detector per watchpoint, each fed
// every step's dense frame. `dwatch replay` and the Python package's `dwatch.replay` both run
// this loop; they differ only in where the matches go.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "sim/model.h"
#include "sim/trace.h"

namespace dw::sim {

// The variables the watchpoints read, each once, in the order first read: what the frames hold.
std::vector<std::string> read_variables(std::span<const HostedWatchpoint> watches);

// Receives the matches of watchpoint `watch` at watch step `t` (as watch::MatchSink does), found
// while the detector observed step `detected` (the last step for those a simultaneous-state
// detector drains at the end).
using ReplaySink = std::function<void(size_t watch, int64_t detected, int64_t t, std::span<const watch::ModuleId> slots,
                                      std::span<const watch::Value> actions)>;

// Replay's work is every step of the trace times every module it names, whatever its lines hold: a
// trace of two lines a million steps apart names a million steps. Past `max_module_steps` (0: the
// default, the larger of kMinModuleSteps and kModuleStepsPerLine per line) it is refused: why, or
// "". A trace that could be read holds its lines, so a real one is far below the default.
inline constexpr uint64_t kModuleStepsPerLine = 1000, kMinModuleSteps = 1'000'000'000;
std::string replay_work_problem(const Trace& trace, uint64_t max_module_steps = 0);

// Entries of the watchpoints' per-step series a replay keeps, over all of them together: only the
// steps where something happened (a PatternMatcher, a message, a match) are kept.
inline constexpr size_t kSeriesEntries = 2'000'000;

// Runs every watchpoint's detector over steps 0 .. step_count - 1 of `frames`; after each step,
// `release(t)` says every watch step up to t is final for every watchpoint (INT64_MAX at the
// end). At the end the detectors decide the last steps (drain), unless `drain` is false: a run
// that a pause stopped did not (Trace::paused), and its watchpoints replayed find what it found.
// Returns each detector's statistics.
std::vector<watch::DetectorStats> replay(FrameReader& frames, int64_t step_count,
                                         std::span<const HostedWatchpoint> watches, const ReplaySink& sink,
                                         const std::function<void(int64_t t)>& release = {}, bool drain = true);

}  // namespace dw::sim
