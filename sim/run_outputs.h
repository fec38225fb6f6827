// What a run writes besides its summary, and the rules it writes them by (docs/design.md §5, §6):
// one place for `dwatch run`, `dwatch replay`, the session's `record` and the Python package.
//
//   - the match log: every match of a `log` or `pause` watchpoint, a watch step written once every
//     watchpoint has decided it; a `count` watchpoint lists none and writes its number at the end;
//   - the trace: a frame a step, its header listing the run's interventions and watchpoints;
//   - the run's end: unless a pause stopped it, or it stopped before its last step, the detectors
//     that decide late drain (docs/design.md §4a) and what they find is written too; a pause is
//     said on the trace's last line, so that replaying it with the run's own watchpoints leaves
//     undecided what the run left undecided.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <ostream>
#include <span>
#include <vector>

#include "sim/match_log.h"
#include "sim/session.h"
#include "sim/trace.h"

namespace dw::sim {

class RunOutputs {
 public:
  // The match log goes to `matches` (null: the matches are only counted); the first `keep` matches
  // of each watchpoint are kept for a summary.
  RunOutputs(const HostedWatches& watches, std::ostream* matches, size_t keep = 1);

  // Writes the trace to `out` as well, from its header on (interventions and watchpoints).
  void record(std::ostream& out, const watch::Universe& universe, std::span<const Intervention> interventions);
  bool recording() const { return trace_ != nullptr; }
  void record_frame(const watch::Frame& frame) { trace_->write(frame); }

  // What watchpoint w found of watch step t: `matches` groups, their slots' ids (none from a `count`
  // one, unless it has actions) and their actions' values. A `count` watchpoint's are counted,
  // the others' logged.
  void found(uint32_t w, int64_t t, uint64_t matches, std::span<const ModuleId> slots,
             std::span<const watch::Value> actions);
  // A live step as the session reports it (Session::StepObserver): what each watchpoint found,
  // then the watch steps every one has decided written. `frame`: the step's, when recording.
  void step(const StepOutput& out, const watch::Frame* frame = nullptr);
  // Every watch step up to t is decided (a replay says so itself).
  void release(int64_t t) { log_.release(t); }

  // A live run of `steps` steps is over, `pause` what stopped it: the drain or the pause line, as
  // the rules above say.
  void end_run(Session& session, const std::optional<Pause>& pause, int64_t steps);
  // Whether replaying `trace` drains at its end: its own watchpoints (none given in their place)
  // do not when a pause stopped the run that recorded it (Trace::paused).
  static bool replay_drains(const Trace& trace, bool own_watchpoints);
  // Everything is written: the steps left, then each `count` watchpoint's number, `counted[w]`
  // (the session's count, which holds what the drain found without groups) or, when not given,
  // what found() was told.
  void finish(std::span<const uint64_t> counted = {});

  // Matches of watchpoint w so far: logged, or counted; and those the log lists (none of a `count`
  // one), of which the first `keep` are kept.
  uint64_t count(uint32_t w) const;
  uint64_t listed(uint32_t w) const { return log_.count(w); }
  const std::vector<MatchLog::Kept>& kept(uint32_t w) const { return log_.kept(w); }

 private:
  HostedWatches watches_;
  MatchLog log_;
  std::vector<watch::MatchSink> sinks_;
  std::vector<uint64_t> counted_;  // per watch: a `count` one's matches
  int64_t max_lag_ = 0;
  std::unique_ptr<TraceWriter> trace_;
};

}  // namespace dw::sim
