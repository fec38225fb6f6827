// The session's watchpoints (docs/design.md §7, "retroactive watchpoints"): what each keeps of a
// step, what the detectors find when the run is over (drain), and watchpoints added, replaced and
// removed at any time, a new one evaluated over the whole history.
#include <algorithm>
#include <string>
#include <vector>

#include "sim/session.h"

namespace dw::sim {

void Session::record_output(const State& state, const StepOutput& out, uint32_t first_watch, uint32_t watch_count) {
  for (uint32_t w = first_watch; w < first_watch + watch_count; ++w) {
    const WatchStepOutput& o = out.watches[w];
    WatchSlot& slot = watches_[w];
    slot.stats.stopped = state.watches[w].stopped;
    slot.stats.stop_reason = state.watches[w].stop_reason;
    if (o.observed) keep_stats(slot, o.stats, out.step);
    keep_matches(w, o.t, out.step, o.matches, o.slots, o.actions);
  }
}

// The totals count every step; the per-step series keeps only the steps where something
// happened (a PatternMatcher, a message, a match), and at most kSeriesEntries entries over all the
// watchpoints together: a run of 10^7 steps and 30 watchpoints held 30 series of a million steps
// each, where memory must follow what happens, not steps times watchpoints.
void Session::keep_stats(WatchSlot& slot, const watch::StepStats& step, int64_t t) {
  const bool happened = step.live || step.created || step.messages || step.matches || step.lost || step.value_messages;
  const bool truncated = slot.stats.steps_truncated;
  slot.stats.max_steps = 0;  // the series is kept here
  slot.stats.add(step);
  slot.stats.steps_truncated = truncated;
  if (!happened) return;
  if (series_entries_ >= kSeriesEntries) {
    slot.stats.steps_truncated = true;
    return;
  }
  slot.stats.steps.push_back(step);
  slot.at.push_back(t);
  ++series_entries_;
}

// What a watchpoint keeps of the `matches` it found of watch step t during step `detected`: a
// `count` one their number, the others each group (`slots`, slot_count ids a match, none for a
// zero-slot watchpoint) and its actions' values.
void Session::keep_matches(uint32_t w, int64_t t, int64_t detected, uint64_t matches, std::span<const ModuleId> slots,
                           std::span<const watch::Value> actions) {
  MatchList& list = watches_[w].matches;
  if (!lists_matches(watches_[w].hosted.action)) {
    list.count(t, detected, matches);
    return;
  }
  list.slots.insert(list.slots.end(), slots.begin(), slots.end());
  list.actions.insert(list.actions.end(), actions.begin(), actions.end());
  list.t.insert(list.t.end(), matches, t);
  list.detected.insert(list.detected.end(), matches, detected);
}

void Session::drain(const DrainSink& sink) {
  forget_end_drain();  // found again, with their statistics, for `sink`
  drain_findings(sink, true);
  drained_ = true;
}

namespace {

// The drain charged against the whole run's PatternMatcher budget as a step is (watch::RunBudget):
// each watchpoint, in the run's charging order, is charged the most any of its drain's detector
// steps wanted (at most its own budget + 1); the one whose running total passes the budget stops,
// its drain reporting nothing, and so does every one after it.
class DrainCharge {
 public:
  DrainCharge(uint64_t limit, int64_t last_step)
      : limit_(limit), when_("in the drain after step " + std::to_string(last_step)) {}
  // The next watchpoint: why it stops before draining (one charged before it passed), or empty.
  std::string next() {
    most_ = 0;
    return passed_ ? over_run_budget(true, limit_, when_) : std::string();
  }
  // One of its drain's steps wanted `wanted` (its own budget: `own`, 0 none): why it stops, or empty.
  std::string charge(uint64_t wanted, uint64_t own) {
    const uint64_t charged = watch::RunBudget::charge(wanted, own);
    if (charged <= most_) return {};
    total_ += charged - most_;
    most_ = charged;
    passed_ = limit_ != 0 && total_ > limit_;
    return passed_ ? over_run_budget(false, limit_, when_) : std::string();
  }

 private:
  uint64_t limit_, total_ = 0, most_ = 0;
  bool passed_ = false;
  std::string when_;
};

// A match the drain found, kept until the watchpoint's charge is known.
struct DrainedMatch {
  uint32_t w = 0;
  bool by_detector = false;
  int64_t t = 0;
  uint64_t rows = 0;
  std::vector<ModuleId> ids;
  std::vector<watch::Value> actions;
};

}  // namespace

// Agents that wait a hop for their neighbours' values decide the run's last steps too, as replay
// of the run's trace does (watch::DistributedDetector::finish), and so do detectors that decide
// late. Charged in the run's charging order (those with actions first); what they found is then
// reported in the order it always was, the agents' before the detectors', each in position order.
void Session::drain_findings(const DrainSink& sink, bool with_stats) {
  DrainCharge budget(options_.run_live_budget, latest_);
  std::vector<DrainedMatch> found;
  const auto stop = [&](uint32_t w, std::string why) {
    WatchState& ws = head_.watches[w];
    ws.stopped = true;
    ws.stop_reason = std::move(why);
    std::erase_if(found, [&](const DrainedMatch& m) {        // its drain reports nothing
      if (m.w == w && !m.by_detector) ws.matches -= m.rows;  // the agents' hosting counted them
      return m.w == w;
    });
  };
  std::vector<uint32_t> order;  // the run's charging order (WatchHosting)
  for (const bool acting : {true, false})
    for (uint32_t w = 0; w < watches_.size(); ++w)
      if (watches_[w].hosted.watchpoint.program.actions.empty() != acting) order.push_back(w);
  for (const uint32_t w : order) {
    WatchSlot& slot = watches_[w];
    WatchState& ws = head_.watches[w];
    const watch::Program& p = slot.hosted.watchpoint.program;
    const uint64_t own = slot.hosted.options.live_budget;
    const bool agents = slot.hosted.runs_on_agents() && p.aggregate_hops > 0;
    if (ws.stopped || (!agents && !ws.detector)) continue;
    if (std::string why = budget.next(); !why.empty()) {
      stop(w, std::move(why));
    } else if (agents) {
      for (int64_t f = std::max<int64_t>(0, head_.step - p.agent_delay()); f <= head_.step - 1 - p.extent_plus; ++f) {
        WatchStepOutput out;
        runtime_->drain_agents(head_, w, f, out);
        const uint64_t wanted = ws.stopped ? own + 1 : out.stats.live + out.stats.messages;
        if (!ws.stopped) found.push_back({w, false, out.t, out.matches, out.slots, out.actions});
        if (std::string why = budget.charge(wanted, own); !why.empty()) {
          stop(w, std::move(why));
          break;
        }
        if (with_stats && out.observed) slot.add_stats(out.stats, latest_);
        if (ws.stopped) break;
      }
    } else {
      const uint32_t k = p.slot_count();
      uint64_t wanted = 0;  // the most a step of the drain is seen to want
      ws.detector->set_sink([&](int64_t t, std::span<const ModuleId> ids, std::span<const watch::Value> actions) {
        const watch::StepStats& last = ws.detector->stats().last;  // the step that decided t
        wanted = std::max(wanted, last.live + last.messages);
        found.push_back(
            {w, true, t, watch::match_rows(ids.size(), k), {ids.begin(), ids.end()}, {actions.begin(), actions.end()}});
      });
      const watch::DetectorStats before = ws.detector->stats();
      ws.detector->finish();
      const watch::DetectorStats& after = ws.detector->stats();
      if (after.observed_steps > before.observed_steps)
        wanted = std::max(wanted, after.last.live + after.last.messages);
      if (after.peak_live > before.peak_live) wanted = std::max(wanted, after.peak_live);
      if (after.stopped && !before.stopped) {  // past its own budget
        wanted = own + 1;
        ws.stopped = true;
        ws.stop_reason = after.stop_reason;
      }
      if (std::string why = budget.charge(wanted, own); !why.empty()) stop(w, std::move(why));
      else if (with_stats) add_drained_stats(w, before, after);
    }
    slot.stats.stopped = ws.stopped;  // whether or not the statistics are kept: the session says why
    slot.stats.stop_reason = ws.stop_reason;
  }
  std::stable_sort(found.begin(), found.end(), [](const DrainedMatch& a, const DrainedMatch& b) {
    return std::pair(a.by_detector, a.w) < std::pair(b.by_detector, b.w);
  });
  for (DrainedMatch& m : found) {
    if (m.by_detector) head_.watches[m.w].matches += m.rows;
    keep_matches(m.w, m.t, latest_, m.rows, m.ids, m.actions);
    if (sink && (m.by_detector || !m.ids.empty())) sink(m.w, m.t, m.ids, m.actions);
  }
}

// The drain's matches join the history (a `pause` one pauses nowhere: pause_at) while the
// watchpoints' own states stay as they were: the session may still simulate past the end, or
// `run` drain for its outputs.
void Session::drain_at_end() {
  if (end_drained_ || drained_ || latest_ != options_.end - 1) return;
  before_end_drain_.clear();
  for (uint32_t w = 0; w < watches_.size(); ++w)
    before_end_drain_.emplace_back(watches_[w].matches.size(), watches_[w].matches.counted.size());
  std::vector<WatchState> watching = head_.watches;
  drain_findings({}, false);
  end_drain_matches_.clear();
  for (uint32_t w = 0; w < watches_.size(); ++w)
    end_drain_matches_.push_back(head_.watches[w].matches - watching[w].matches);
  head_.watches = std::move(watching);
  end_drained_ = true;
}

void Session::forget_end_drain() {
  if (!end_drained_) return;
  for (uint32_t w = 0; w < watches_.size() && w < head_.watches.size(); ++w) {  // a stop in the drain too
    watches_[w].stats.stopped = head_.watches[w].stopped;
    watches_[w].stats.stop_reason = head_.watches[w].stop_reason;
  }
  for (uint32_t w = 0; w < watches_.size() && w < before_end_drain_.size(); ++w) {
    MatchList& list = watches_[w].matches;
    const watch::Program& program = watches_[w].hosted.watchpoint.program;
    const size_t keep = before_end_drain_[w].first;
    list.t.resize(keep);
    list.detected.resize(keep);
    list.slots.resize(keep * program.slot_count());
    list.actions.resize(keep * program.actions.size());
    list.counted.resize(before_end_drain_[w].second);
  }
  end_drained_ = false;
}

// The drain's work, as one more entry of the session's series.
void Session::add_drained_stats(uint32_t w, const watch::DetectorStats& before, const watch::DetectorStats& after) {
  watch::StepStats drained;
  drained.step = latest_;
  drained.live_by_filled.assign(watches_[w].hosted.watchpoint.program.slot_count() + 1, 0);
  for (size_t i = 0; i < after.created_by_filled.size() && i < before.created_by_filled.size(); ++i)
    drained.live_by_filled[i] = after.created_by_filled[i] - before.created_by_filled[i];
  drained.created = after.created - before.created;
  drained.messages = after.messages - before.messages;
  drained.bytes = after.bytes - before.bytes;
  drained.lost = after.lost - before.lost;
  drained.value_messages = after.value_messages - before.value_messages;
  drained.matches = after.matches - before.matches;
  drained.seconds = after.seconds - before.seconds;
  if (drained.created || drained.messages || drained.matches || drained.lost) watches_[w].add_stats(drained, latest_);
}

std::vector<uint64_t> Session::match_counts(uint32_t w, int64_t from, int64_t to) const {
  std::vector<uint64_t> counts(static_cast<size_t>(std::max<int64_t>(0, to - from + 1)), 0);
  const MatchList& list = watches_[w].matches;
  for (const MatchList::Counted& c : list.counted)
    if (c.t >= from && c.t <= to) counts[static_cast<size_t>(c.t - from)] += c.matches;
  const size_t first = list.at(from).first;
  for (size_t i = first; i < list.size() && list.t[i] <= to; ++i) ++counts[static_cast<size_t>(list.t[i] - from)];
  return counts;
}

int Session::watch_index(std::string_view name) const {
  const std::optional<uint32_t> w = watches_.find(name);
  return w ? static_cast<int>(*w) : -1;
}

std::optional<uint32_t> Session::set_watch(HostedWatchpoint watch, const Control& control, std::string* why) {
  const auto refuse = [why](std::string reason) {
    if (why) *why = std::move(reason);
    return std::nullopt;
  };
  const std::optional<uint32_t> replaces = watches_.find(watch.watchpoint.name);
  if (!replaces && watches_.size() >= watch::kMaxWatchpoints)
    return refuse("a session holds at most " + std::to_string(watch::kMaxWatchpoints) +
                  " watchpoints: unwatch one first");
  if (!has_history())
    return refuse(control.stopped() ? "cancelled" : "the session keeps no history to evaluate a watchpoint over");
  forget_end_drain();  // drained again with the new watchpoint
  const bool acts = !watch.watchpoint.program.actions.empty() ||
                    (replaces && !watches_[*replaces].hosted.watchpoint.program.actions.empty());
  // The new watchpoint goes in last; then, replacing one, into its place (the others keep theirs).
  watches_.add(std::move(watch));
  const uint32_t w = watches_.size() - 1;
  if (acts) {
    // Its actions change the states themselves (docs/design.md §4b): the history is simulated again.
    if (replaces) watches_.move_last_to(*replaces);
    rebuild_runtime();
    resimulate();
    return replaces.value_or(w);
  }
  rebuild_runtime();
  bool evaluated = false;
  try {
    evaluated = evaluate_over_history(w, control);
  } catch (...) {
    watches_.pop_back();
    rebuild_runtime();
    throw;
  }
  if (!evaluated) {  // cancelled: as it was
    watches_.pop_back();
    rebuild_runtime();
    drain_at_end();
    return refuse("cancelled");
  }
  if (replaces) {
    const auto move_last = [r = *replaces](std::vector<WatchState>& v) {
      v[r] = std::move(v.back());
      v.pop_back();
    };
    watches_.move_last_to(*replaces);
    move_last(head_.watches);
    for (State& k : keyframes_) move_last(k.watches);
    rebuild_runtime();
  }
  recount_history();
  look_ahead({});
  drain_at_end();
  return replaces.value_or(w);
}

// The new watchpoint at position w (the last) evaluated alone over the history, from the first
// keyframe, its state copied into every keyframe on the way and then the head's. False when
// cancelled (its states are then in no keyframe).
bool Session::evaluate_over_history(uint32_t w, const Control& control) {
  State s = acting_part(keyframes_[0]);
  restore_bodies(s, 0);
  s.watches.push_back(runtime_->initial_watch_state(w));
  std::vector<WatchState> at_keyframe{s.watches[w]};  // its state at keyframes_[i]
  size_t added = state_bytes(State{.watches = {at_keyframe[0]}});
  std::vector<uint8_t> watching(w + 1, 0);
  watching[w] = 1;
  StepOutput out;
  size_t charged_at = 0;                              // run_charges_[charged_at - 1] holds this step's total
  std::vector<std::pair<int64_t, uint64_t>> charges;  // run_charges_ with its own
  while (s.step <= latest_ || (s.step % interval_ == 0 && s.step / interval_ < int64_t(keyframes_.size()))) {
    if (s.step % interval_ == 0 && s.step > 0) {
      at_keyframe.push_back(s.watches[w]);
      added += state_bytes(State{.watches = {at_keyframe.back()}});
      // Keyframes must stay within the budget with the new watchpoint's states in them too.
      while (keyframes_.size() > 1 &&
             history_bytes_ + added / at_keyframe.size() * keyframes_.size() > options_.history_bytes) {
        thin_keyframes();
        std::vector<WatchState> kept;
        for (size_t i = 0; i < at_keyframe.size(); i += 2) kept.push_back(std::move(at_keyframe[i]));
        at_keyframe = std::move(kept);
        added = 0;
        for (const WatchState& ws : at_keyframe) added += state_bytes(State{.watches = {ws}});
      }
    }
    if (s.step > latest_) break;
    if (control.stopped()) return false;
    // Charged after every other watchpoint, as a run that had it last from step 0 charges it.
    while (charged_at < run_charges_.size() && run_charges_[charged_at].first <= s.step) ++charged_at;
    runtime_->charge_before(charged_at == 0 ? 0 : run_charges_[charged_at - 1].second);
    step(s, out, watching);
    if (const uint64_t total = runtime_->charged(); total != (charges.empty() ? 0 : charges.back().second))
      charges.push_back({s.step, total});
    world_on_ = nullptr;  // `s` is a local
    record_output(s, out, w, 1);
    if (control.progress) control.progress(s.step, latest_ + 1);
  }
  for (size_t i = 0; i < keyframes_.size(); ++i) keyframes_[i].watches.push_back(std::move(at_keyframe[i]));
  head_.watches.push_back(std::move(s.watches[w]));
  run_charges_ = std::move(charges);
  view_valid_ = false;
  measured_for_ = kNotMeasured;
  return true;
}

// A new watchpoint may have a longer lag: the current step is decided again, as far as the end allows.
void Session::look_ahead(const StepObserver& observer) {
  const int64_t need = std::min(current_ + max_lag(), options_.end - 1);
  while (latest_ < need) step_head(observer);
}

bool Session::remove_watch(std::string_view name) {
  const std::optional<uint32_t> found = watches_.find(name);
  if (!found) return false;
  const uint32_t w = *found;
  const bool acted = !watches_[w].hosted.watchpoint.program.actions.empty();
  forget_end_drain();
  watches_.erase(w);
  head_.watches.erase(head_.watches.begin() + std::ptrdiff_t{w});
  for (State& k : keyframes_) k.watches.erase(k.watches.begin() + std::ptrdiff_t{w});
  view_valid_ = false;
  measured_for_ = kNotMeasured;
  rebuild_runtime();
  recount_history();
  if (acted) resimulate();
  drain_at_end();
  return true;
}

}  // namespace dw::sim
