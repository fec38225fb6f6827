// A run of a model: the state, the ring of snapshots behind it (DESIGN §7), the matches found and
// the watchpoints' statistics, with rollback and resume. A resumed run equals one that never
// rolled back: the state is all there is, and stepping it is deterministic.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "sim/runtime.h"

namespace dw::sim {

struct RunOptions {
  unsigned threads = 1;
  size_t snapshots = 0;  // the states after the last K steps are kept for rollback
};

// The matches of one watchpoint, in the order found (by t, then by slot ids).
struct MatchList {
  std::vector<int64_t> t;         // the match's watch step
  std::vector<int64_t> detected;  // the step during which it was found (t + the detector's lag)
  std::vector<ModuleId> slots;    // slot_count ids per match
  size_t size() const { return t.size(); }
};

// A `pause` watchpoint matched.
struct Pause {
  uint32_t watch = 0;
  int64_t t = 0;                // the match's step
  int64_t detected = 0;         // the step during which it was found
  std::vector<ModuleId> group;  // the first match of that step, in slot order
  uint64_t matches = 0;         // matches of that watchpoint at that step
};

class Run {
 public:
  // `model` and `world` must outlive the run.
  Run(const Model& model, World& world, RunOptions options);

  const Model& model() const { return runtime_.model(); }
  const State& state() const { return state_; }
  // Steps run so far (the state's values are those of step steps_run() - 1).
  int64_t steps_run() const { return state_.step; }

  using StepObserver = std::function<void(const State&, const StepOutput&)>;
  // Runs steps until `end` have run or a `pause` watchpoint fires (a pause fires once per
  // detection step: a resumed run goes past it). Throws ProgramError when a program fails.
  std::optional<Pause> run_until(int64_t end, const StepObserver& observer = {});

  // Restores the state as it was right after step t ran (t = -1: before step 0). Possible for
  // the last `snapshots` steps; false otherwise. Matches and statistics found later are dropped.
  bool rollback_to(int64_t t);
  // The earliest step rollback_to accepts, or nothing when no snapshot is held.
  std::optional<int64_t> oldest_snapshot() const;

  // Matches of `log` and `pause` watchpoints (a `count` watchpoint's list stays empty).
  const MatchList& matches(uint32_t watch) const { return matches_[watch]; }
  uint64_t match_count(uint32_t watch) const { return state_.watches[watch].matches; }
  // Statistics over the steps run so far (the per-step series is the run's own).
  const watch::DetectorStats& stats(uint32_t watch) const { return stats_[watch]; }

 private:
  void take_snapshot();
  void record(const StepOutput& out);

  Runtime runtime_;
  RunOptions options_;
  State state_;
  std::vector<State> ring_;  // states after consecutive steps, the oldest at ring_start_
  size_t ring_start_ = 0;
  std::vector<MatchList> matches_;
  std::vector<watch::DetectorStats> stats_;
  std::vector<std::vector<int64_t>> stats_step_;  // per watch: the run step of each series entry
  int64_t pause_guard_ = -1;                      // pauses detected at or before this step have fired
  StepOutput out_;
};

}  // namespace dw::sim
