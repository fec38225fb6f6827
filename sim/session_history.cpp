// The session's history (docs/design.md §7): keyframes every K steps within their memory budget,
// the future dropped at a branch, and the whole history simulated again when the watchpoints with
// actions change.
#include <algorithm>
#include <chrono>

#include "sim/body_slices.h"
#include "sim/session.h"

namespace dw::sim {

// A keyframe before every step that is a multiple of K. When they outgrow the budget, or would
// by the session's end at their present size, every other one goes and K doubles (keyframe 0
// always stays). Dropped keyframes lend their storage to the next ones: copying into a state
// that has the shape already allocates nothing.
void Session::take_keyframe() {
  if (!has_history()) return;
  const auto due = [&] {
    return head_.step % interval_ == 0 && head_.step / interval_ == static_cast<int64_t>(keyframes_.size());
  };
  if (!due()) return;
  // A keyframe that would not fit is not copied only to be dropped: the keyframes thin first (K
  // doubles), after which this step may be no keyframe's. (At a million modules a copy is
  // hundreds of MB, and a budget smaller than one keyframe keeps keyframe 0 alone.) The live
  // state's own estimate counts the room its buffers grew to; a copy is the size of the others.
  if (!keyframes_.empty()) {
    const size_t bytes = history_bytes_ / keyframes_.size();
    while (any_rank(options_.ranks, history_bytes_ + bytes > options_.history_bytes)) {
      thin_keyframes();
      if (!due()) return;
    }
  }
  const auto started = std::chrono::steady_clock::now();
  // The bodies are kept apart, in chunks shared with the last keyframe's where they did not
  // change, and over ranks a slice per rank (sim/body_slices.h).
  Bodies live = std::move(head_.bodies);
  if (spare_.empty()) {
    keyframes_.push_back(head_);
  } else {
    spare_bytes_ -= state_bytes(spare_.back());
    keyframes_.push_back(std::move(spare_.back()));
    spare_.pop_back();
    keyframes_.back() = head_;
  }
  head_.bodies = std::move(live);
  const BodySlice* last = body_slices_.empty() ? nullptr : &body_slices_.back();
  const int rank = options_.ranks ? options_.ranks->rank() : 0, ranks = options_.ranks ? options_.ranks->ranks() : 1;
  BodySlice bodies(head_.bodies, rank, ranks, last);  // made before the list may move `last`
  history_bytes_ += bodies.bytes_beyond(last);
  body_slices_.push_back(std::move(bodies));
  const double copy_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  history_bytes_ += state_bytes(keyframes_.back());
  if (keyframes_.size() == 1 || keyframes_.back().graph != keyframes_[keyframes_.size() - 2].graph)
    history_bytes_ += graph_bytes(*keyframes_.back().graph);
  auto over_budget = [&] {
    const size_t budget = options_.history_bytes;
    if (history_bytes_ > budget) return true;
    // At this size a keyframe, how many would the end need?
    const int64_t left = options_.end - head_.step;
    return left > 0 && history_bytes_ + static_cast<size_t>(left / interval_) * (history_bytes_ / keyframes_.size()) >
                           budget + budget / 2;
  };
  // Over several ranks each measures its own part; they thin together, so that every rank's
  // history steps alike (in one process any_rank is the decision itself).
  while (keyframes_.size() > 1 && any_rank(options_.ranks, over_budget())) thin_keyframes();
  // Nor may they cost the live run more than a small share of its time: where a step is cheap
  // beside a copy of the state, keyframes are further apart, as long as a seek's stepping from
  // one stays short.
  if (keyframes_.size() > 1 &&
      any_rank(options_.ranks, copy_seconds > options_.keyframe_time_share * double(interval_) * step_seconds_ &&
                                   2 * double(interval_) * step_seconds_ <= kSeekStepSeconds))
    thin_keyframes();
  // Spares are storage lent ahead, never worth going past the budget: a keyframe copied into one
  // may have outgrown what it held when it was kept.
  while (!spare_.empty() && history_bytes_ + spare_bytes_ > options_.history_bytes) {
    spare_bytes_ -= state_bytes(spare_.back());
    spare_.pop_back();
  }
}

// A copy of keyframe `index` gets its bodies back (over ranks from the ranks' slices: a collective
// call, made alike on every rank: every rank restores the same keyframes).
void Session::restore_bodies(State& copy, size_t index) const {
  copy.bodies = bodies_from_slices(body_slices_[index], options_.ranks);
}

// Every other keyframe goes (keyframe 0 stays) and K doubles. A dropped one is kept as storage for
// the next only while the keyframes and the spares together stay within the budget.
void Session::thin_keyframes() {
  std::vector<State> kept, dropped;
  for (size_t i = 0; i < keyframes_.size(); ++i) (i % 2 == 0 ? kept : dropped).push_back(std::move(keyframes_[i]));
  keyframes_ = std::move(kept);
  std::vector<BodySlice> kept_slices;
  for (size_t i = 0; i < body_slices_.size(); i += 2) kept_slices.push_back(std::move(body_slices_[i]));
  body_slices_ = std::move(kept_slices);
  interval_ *= 2;
  recount_history();
  for (State& d : dropped) {
    const size_t bytes = state_bytes(d);
    if (spare_.size() >= kSpareKeyframes || history_bytes_ + spare_bytes_ + bytes > options_.history_bytes) break;
    d.graph.reset();  // nor does it keep a graph of the past alive
    spare_.push_back(std::move(d));
    spare_bytes_ += bytes;
  }
}

void Session::recount_history() {
  history_bytes_ = 0;
  for (size_t i = 0; i < keyframes_.size(); ++i) {
    history_bytes_ += state_bytes(keyframes_[i]) + body_slices_[i].bytes_beyond(i > 0 ? &body_slices_[i - 1] : nullptr);
    if (i == 0 || keyframes_[i].graph != keyframes_[i - 1].graph) history_bytes_ += graph_bytes(*keyframes_[i].graph);
  }
}

// Forgets what was found after step `through` (matches detected later, statistics of later steps).
void Session::truncate_history(int64_t through) {
  forget_end_drain();
  while (!run_charges_.empty() && run_charges_.back().first > through) run_charges_.pop_back();
  series_entries_ = 0;
  for (uint32_t w = 0; w < watches_.size(); ++w) {
    WatchSlot& slot = watches_[w];
    const watch::Program& program = slot.hosted.watchpoint.program;
    slot.matches.drop_after(through, program.slot_count(), program.actions.size());
    const size_t entries =
        static_cast<size_t>(std::upper_bound(slot.at.begin(), slot.at.end(), through) - slot.at.begin());
    std::vector<watch::StepStats> series(
        slot.stats.steps.begin(),
        slot.stats.steps.begin() + static_cast<ptrdiff_t>(std::min(entries, slot.stats.steps.size())));
    slot.at.resize(entries);
    const bool truncated = slot.stats.steps_truncated;
    slot.stats = watch::DetectorStats{};
    for (const watch::StepStats& s : series) slot.stats.add(s);
    slot.stats.steps_truncated = truncated;
    series_entries_ += series.size();
    slot.stats.stopped = head_.watches[w].stopped;
    slot.stats.stop_reason = head_.watches[w].stop_reason;
  }
}

void Session::branch_here() {
  materialize(current_, {});
  head_ = std::move(view_);
  head_out_ = std::move(view_out_);
  view_valid_ = false;
  measured_for_ = kNotMeasured;
  world_on_ = nullptr;
  latest_ = current_;
  const size_t keep = static_cast<size_t>((current_ + 1) / interval_) + 1;
  if (keyframes_.size() > keep) {
    keyframes_.resize(keep);
    body_slices_.resize(keep);
    recount_history();
  }
  truncate_history(current_);
}

// Watchpoints' actions are part of the simulation (docs/design.md §4b): when the watchpoints with actions
// change, every state from step 0 may change, so the history is simulated again from the initial
// state, each intervention and program replacement at its step, as far as it went, and the cursor
// goes back where it was.
void Session::resimulate() {
  const int64_t latest = latest_, current = current_;
  head_ = runtime_->initial_state();
  world_on_ = &head_;
  keyframes_.clear();
  body_slices_.clear();
  interval_ = 1;
  history_bytes_ = 0;
  run_charges_.clear();
  series_entries_ = 0;
  end_drained_ = false;
  for (uint32_t w = 0; w < watches_.size(); ++w) {
    watches_[w].matches = {};
    watches_[w].stats = {};
    watches_[w].at.clear();
  }
  latest_ = current_ = -1;
  view_valid_ = false;
  measured_for_ = kNotMeasured;
  failure_.reset();
  take_keyframe();
  while (latest_ < latest) step_head({});
  current_ = latest_;
  seek(current);
}

}  // namespace dw::sim
