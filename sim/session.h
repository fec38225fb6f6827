// The debugging session (docs/design.md §7): one object that the command line, the window, scripts and
// tests all drive. It owns the run's whole history, step 0 to the latest, and a cursor on it:
//
//   - keyframes (full states) every K steps, K doubling whenever they outgrow their memory budget;
//     any step is reached by restoring the keyframe before it and stepping on, so looking at the
//     past never loses the future;
//   - its watchpoints, in slots with stable handles (sim/watch_slots.h), each with its matches
//     and statistics over the history, indexed by step; it starts with the scenario's (Model::watches);
//   - interventions (set, remove, push) at the current step, which cut the future and start a
//     branch, and the scenario's scheduled ones ([[event]]), applied as the steps run;
//   - watchpoints added, replaced or removed at any time: a new one is evaluated over the whole
//     history, so its matches equal those of a run that had it from step 0.
//
// Steps and positions: the *current* step t is the one shown; its state is the one after step t
// ran (the values of step t). -1 is before step 0. The *latest* step is the last one simulated
// on this branch. A watchpoint with lag λ has decided step t once step t + λ exists; the cursor
// only moves onto steps every watchpoint has decided (simulating ahead as far as the session's
// end allows), so a view of the current step shows all its matches, and a `pause` match stops
// the cursor at the match's own step.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <ostream>
#include <span>
#include <stop_token>
#include <string>
#include <utility>
#include <vector>

#include "sim/body_slices.h"
#include "sim/intervention.h"
#include "sim/runtime.h"
#include "sim/watch_slots.h"

namespace dw::sim {

struct SessionOptions {
  unsigned threads = 1;
  // The scenario's steps: the session does not simulate ahead past step end - 1 (a run asked to
  // go further may). 0: ahead only as far as each run is asked to go.
  int64_t end = 0;
  // Memory for keyframes (over ranks, for all of theirs); K doubles to stay within it (keyframe 0
  // always stays). 0: no history, for measuring the runtime alone: the session can then neither
  // seek back, branch from the past, nor evaluate a new watchpoint over the past.
  size_t history_bytes = size_t{256} << 20;
  std::vector<Intervention> events;  // scheduled interventions ([[event]]), any order
  // This process is one rank of a run over several (docs/design.md §12): every rank makes the same calls
  // on its session, which steps the rank's modules and takes every decision alike on all ranks.
  RankExchange* ranks = nullptr;
  Partition partition = Partition::Auto;  // how the modules are shared among the ranks
  // The share of the live run's time keyframes may take, at most: where a step is cheap beside a
  // copy of the state they are further apart. (Infinite: only the budget spaces them, for tests
  // that count them.)
  double keyframe_time_share = 0.08;
  // Most PatternMatchers all its watchpoints together keep alive in a step (watch::RunBudget); 0: none.
  uint64_t run_live_budget = kDefaultRunBudget;
};

// Lets a long operation be cancelled between steps and report how far it got. A cancelled
// operation leaves the session as it was (seek, watch) or where it had got to (a run): what
// follows never depends on where a cancel fell.
struct Control {
  std::stop_token stop;
  std::function<void(int64_t done, int64_t total)> progress;
  bool stopped() const { return stop.stop_requested(); }
};

// A program's failure that stopped the run: the step it was running and the module.
struct ProgramFailure {
  int64_t step = 0;
  ModuleId module = 0;
  std::string message;
};

// A `pause` watchpoint matched at the current step, or the watchpoint a run was asked to stop at
// the next match of (`run --to-match W`).
struct Pause {
  uint32_t watch = 0;
  bool asked = false;           // the match of the run's `to_match`, not a pause action
  int64_t t = 0;                // the match's step
  int64_t detected = 0;         // the step during which it was found
  std::vector<ModuleId> group;  // the first match of that step, in slot order
  uint64_t matches = 0;         // matches of that watchpoint at that step
};

class Session {
 public:
  // `model` and `world` must outlive the session, which never changes the model (docs/design.md
  // §2): it hosts the model's watchpoints, the scenario's, as its first, in slots of its own.
  Session(const Model& model, World& world, SessionOptions options);
  // A copy of `other` of its own (Python's Session.fork, snapshot and restore): at the same step
  // of the same history and branch, with the same watchpoints and everything they found, stepping
  // `world` (its own, of the same model, or other's when the copy is only kept to be copied back)
  // on `threads` threads (the results are the same on any). What either does next leaves the other
  // as it was, and both go on as other would have: the same states, hashes and matches. In one
  // process only (not over ranks: std::logic_error).
  Session(const Session& other, World& world, unsigned threads);
  ~Session();

  const Model& model() const { return model_; }
  int64_t current() const { return current_; }
  int64_t latest() const { return latest_; }
  int64_t end() const { return options_.end; }
  unsigned threads() const { return runtime_->threads(); }

  // Called with every step simulated for the first time on this branch (the head's state and
  // what the watchpoints reported).
  using StepObserver = std::function<void(const State&, const StepOutput&)>;

  // Moves the current step on until `end` steps have run (current = end - 1), stopping early at
  // a `pause` match's step (returned) or when cancelled. Steps already simulated are revisited,
  // new ones simulated. With `to_match`, it stops at that watchpoint's next match too (a `count`
  // watchpoint keeps no matches to stop at). Throws ProgramError when a program fails.
  std::optional<Pause> run_until(int64_t end, const StepObserver& observer = {}, const Control& control = {},
                                 std::optional<uint32_t> to_match = std::nullopt);
  // The run is over (`dwatch run`'s last call, docs/design.md §4a): the detectors that decide late, in
  // simultaneous-state mode, drain their PatternMatchers over the last step's links. What they
  // find joins the history as detected at the latest step (a `pause` one does not pause) and goes
  // to `sink`. The session simulates no further step afterwards.
  using DrainSink = std::function<void(uint32_t watch, int64_t t, std::span<const ModuleId> slots,
                                       std::span<const watch::Value> actions)>;
  void drain(const DrainSink& sink = {});
  // Makes step t current (-1 ≤ t ≤ latest). False when cancelled (nothing changed then).
  bool seek(int64_t t, const Control& control = {});
  // Simulates ahead until every watchpoint has decided step t, past the session's end if need be.
  void decide(int64_t t, const StepObserver& observer = {}, const Control& control = {});
  // Through which step every watchpoint (or watchpoint w) has decided; latest() without any, and
  // at the scenario's end, where the session has drained (docs/design.md §4c, "Run's end").
  int64_t decided() const;
  int64_t decided(uint32_t w) const { return end_drained_ ? latest_ : latest_ - watches_[w].hosted.lag(); }

  // An intervention at the current step t, applied at the start of step t + 1 (`at` is set so):
  // the future after t is dropped and the next steps simulate the change. An error message when
  // it names no module or variable, or pushes without physics; empty when done.
  std::string intervene(Intervention intervention);
  // Why a push on module m at the current step would move nothing, as things stand (latched to
  // the ground, or making a lattice move); empty when it may move it. A program's move in the
  // next step can still free a latched module, so the push is made either way and its answer
  // carries this as a warning.
  std::string push_moves_nothing(ModuleId m);
  // Every intervention of this branch, scheduled or made, in the order they apply.
  const std::vector<Intervention>& interventions() const { return interventions_; }

  // Runs each replacement in place of its program from the step after the current one on (scripts
  // changed and loaded again): the future after the current step is dropped, as with an
  // intervention, and the past keeps the programs it ran, so re-simulating it gives it again. An
  // error message, and nothing replaced, when one does not keep its program's variables; empty
  // when done.
  struct Replacement {
    uint32_t program;
    std::shared_ptr<const HostProgram> with;
  };
  std::string replace_programs(std::vector<Replacement> replacements);
  // The first step this branch runs a replaced program from, after step 0; none when every
  // program runs as loaded (or was replaced before step 0).
  std::optional<int64_t> first_replacement() const {
    for (const ProgramVersion& v : program_versions_)
      if (v.from > 0) return v.from;
    return std::nullopt;
  }

  // The program failure that stopped the run at step latest() + 1: nothing once a step after the
  // latest went through, or the future changed (an intervention, a program replaced).
  const std::optional<ProgramFailure>& failure() const { return failure_; }

  // The watchpoints, at their positions (the order the run hosts them in), each with what it
  // found over the history.
  const WatchSlots& watches() const { return watches_; }
  // Adds a watchpoint, or replaces the one with its name (at its position, under a new id), and
  // evaluates it over the whole history. Its position; or nothing, nothing changed, and `why` says
  // why not: a session holds at most watch::kMaxWatchpoints, needs its history to evaluate one, and
  // may be cancelled ("cancelled").
  std::optional<uint32_t> set_watch(HostedWatchpoint watch, const Control& control = {}, std::string* why = nullptr);
  // What watchpoint w does with its matches from now on (`action W log|pause|count`): nothing is
  // evaluated again, the matches found stay as they are (a `count` watchpoint keeps only their
  // number, so one switched from `count` lists only those found after, and counted the others),
  // and a pause looks at the new action.
  void set_action(uint32_t w, MatchAction action) { watches_[w].hosted.action = action; }
  // Removes the watchpoint with this name; false when there is none.
  bool remove_watch(std::string_view name);
  // The position of the watchpoint with this name, or -1.
  int watch_index(std::string_view name) const;

  // The full state at the current step (restored on demand), and after the latest step.
  const State& state();
  const State& head() const { return head_; }
  // The current step's state hash (over ranks, a collective call).
  StateHash hash() { return runtime_->hash(state()); }
  // The variables of every module in `state` (one of this session's): over ranks, gathered from
  // the rank of each (a collective call).
  std::vector<int64_t> whole_values(const State& state) { return runtime_->whole_values(state); }
  // N(m, t) of every module in `graph` (a state's or a step's): over ranks, gathered from the rank
  // of each (a collective call).
  std::shared_ptr<const NeighborGraph> whole_graph(const std::shared_ptr<const NeighborGraph>& graph) {
    return runtime_->whole_graph(graph);
  }
  // Bytes this rank sent to the other ranks (Runtime::bytes_to_ranks).
  uint64_t bytes_to_ranks() const { return runtime_->bytes_to_ranks(); }
  double world_seconds() const { return runtime_->world_seconds(); }
  Partition partition() const { return runtime_->partition(); }
  // What the watchpoints saw at the current step besides the values: presence and N(m, t).
  std::span<const uint8_t> seen_present();
  const NeighborGraph& seen_graph();
  // The pose module m had when its neighbours of the current step, N(m, current()), were measured:
  // at the end of step current() - 1 (docs/design.md §2), where state() holds the poses after
  // the current step's physics. Read from the history when asked (the view goes back to that step
  // and on again, a seek's steps; the poses are kept until the cursor moves or the history
  // changes), so a run that never asks keeps nothing more. Nothing without bodies, when the
  // session keeps no history (the step before the latest is not kept), or when cancelled.
  std::optional<Pose> measured_pose(ModuleId m, const Control& control = {});

  // Matches of `log` and `pause` watchpoints over the history (a `count` one's keeps only their
  // number per step, MatchList::counted).
  const MatchList& matches(uint32_t w) const { return watches_[w].matches; }
  uint64_t match_count(uint32_t w) const {
    return head_.watches[w].matches + (end_drained_ && w < end_drain_matches_.size() ? end_drain_matches_[w] : 0);
  }
  // Matches per step of steps [from, to], for a timeline.
  std::vector<uint64_t> match_counts(uint32_t w, int64_t from, int64_t to) const;
  // Statistics over the history (the per-step series is the session's own).
  const watch::DetectorStats& stats(uint32_t w) const { return watches_[w].stats; }
  // One variable of one module over steps [from, to] (to ≤ latest), re-simulated from the
  // keyframes; nothing when cancelled.
  // `present`, when given, gets whether m was present at each of those steps (its values then stale).
  std::optional<std::vector<int64_t>> series(ModuleId m, int column, int64_t from, int64_t to,
                                             const Control& control = {}, std::vector<uint8_t>* present = nullptr);
  // Every variable of module m over steps [from, to] in one pass: (to - from + 1) rows of
  // model().variable_count() values.
  std::optional<std::vector<int64_t>> module_series(ModuleId m, int64_t from, int64_t to, const Control& control = {},
                                                    std::vector<uint8_t>* present = nullptr);
  // Writes steps 0..latest as a wptrace v1 trace whose header lists the interventions. An error
  // message, or empty; false-y when cancelled is reported as "cancelled".
  std::string record(std::ostream& out, const Control& control = {});

  // The history's shape: keyframe interval K, keyframes held, and the estimated bytes they and
  // the dropped ones kept as storage for the next hold.
  bool has_history() const { return options_.history_bytes > 0; }
  int64_t keyframe_interval() const { return interval_; }
  size_t keyframes() const { return keyframes_.size(); }
  size_t history_bytes() const { return history_bytes_ + spare_bytes_; }

 private:
  void step(State& state, StepOutput& out, std::span<const uint8_t> watching = {});
  // What re-simulating the values from `keyframe` needs: its simulation part, and the states of
  // the watchpoints with actions, which act on the simulation (Runtime::step always steps them).
  State acting_part(const State& keyframe) const;
  void step_head(const StepObserver& observer);
  void look_ahead(const StepObserver& observer);
  void take_keyframe();
  void thin_keyframes();
  void recount_history();
  void record_output(const State& state, const StepOutput& out, uint32_t first_watch, uint32_t watch_count);
  void keep_stats(WatchSlot& slot, const watch::StepStats& step, int64_t t);
  void truncate_history(int64_t through);
  std::optional<Pause> pause_at(int64_t t, std::optional<uint32_t> to_match) const;
  bool materialize(int64_t t, const Control& control);
  void rebuild_runtime();
  void branch_here();  // the current step becomes the head: the future is dropped
  void resimulate();
  // What the detectors and agents still hold decided over the last step (`drain`); `with_stats`:
  // their work joins the statistics too.
  void drain_findings(const DrainSink& sink, bool with_stats);
  // At the scenario's last step the session drains a copy of the watchpoints' state, so that it
  // reports what `run` and `replay` report, and can still simulate on: the drain's matches are
  // forgotten when the head moves past the end, the history is cut or the watchpoints change.
  void drain_at_end();
  void forget_end_drain();
  void keep_matches(uint32_t w, int64_t t, int64_t detected, uint64_t matches, std::span<const ModuleId> slots,
                    std::span<const watch::Value> actions);
  bool evaluate_over_history(uint32_t w, const Control& control);
  void add_drained_stats(uint32_t w, const watch::DetectorStats& before, const watch::DetectorStats& after);
  void drop_changes_after(int64_t at);
  void decide_again(int64_t simulated_before);  // session_interventions.cpp: after a branch starts
  int64_t max_lag() const;

  const Model& model_;
  World& world_;
  SessionOptions options_;
  WatchSlots watches_;  // the runtime hosts them where they are
  std::unique_ptr<Runtime> runtime_;
  std::vector<Intervention> interventions_;  // sorted by `at`, stable
  struct ProgramVersion {
    int64_t from;  // the first step it runs
    uint32_t program;
    std::shared_ptr<const HostProgram> replacement;
  };
  std::vector<ProgramVersion> program_versions_;  // sorted by `from`
  std::optional<ProgramFailure> failure_;

  State head_;  // after step latest_
  bool drained_ = false;
  // The end's drain is in the matches (drain_at_end): each watchpoint's matches and counted
  // entries before it.
  bool end_drained_ = false;
  std::vector<std::pair<size_t, size_t>> before_end_drain_;
  std::vector<uint64_t> end_drain_matches_;  // how many each found
  StepOutput head_out_;
  int64_t latest_ = -1, current_ = -1;
  State view_;  // after some step <= latest_, when view_valid_; the current step's when current_ < latest_
  StepOutput view_out_;
  bool view_valid_ = false;
  // The poses at the end of step measured_for_ - 1, from which N(measured_for_) was measured
  // (measured_pose), once asked; kNotMeasured when none are, or the history changed since.
  static constexpr int64_t kNotMeasured = -2;
  PagedArray<Pose, CellPose> measured_poses_;
  int64_t measured_for_ = kNotMeasured;
  const State* world_on_ = nullptr;  // the state the world last stepped (it must be told of a change)

  std::vector<State> keyframes_;  // keyframes_[i]: the state before step i * interval_
  // keyframes_[i].bodies is empty: body_slices_[i] holds them (over ranks, this rank's share).
  std::vector<BodySlice> body_slices_;
  void restore_bodies(State& copy, size_t index) const;
  static constexpr size_t kSpareKeyframes = 4;
  std::vector<State> spare_;  // dropped keyframes, their storage for the next (within the budget)
  size_t spare_bytes_ = 0;
  static constexpr double kSeekStepSeconds = 0.025;  // stepping from a keyframe takes at most about this
  double step_seconds_ = 0;                          // a live step's time, smoothed
  int64_t interval_ = 1;
  size_t history_bytes_ = 0;
  // What the steps charged the whole run's PatternMatcher budget, as runs: (the first step, the
  // total each step from it on charged), in step order, nothing before the first (a few entries
  // where every step charges alike). A watchpoint evaluated alone over the history is charged
  // after them.
  std::vector<std::pair<int64_t, uint64_t>> run_charges_;
  // Entries of the watchpoints' per-step series, all together (keep_stats), at most kSeriesEntries
  // (about 130 bytes each).
  static constexpr size_t kSeriesEntries = 2'000'000;
  size_t series_entries_ = 0;
};

}  // namespace dw::sim
