#include "sim/session.h"

#include <algorithm>
#include <chrono>

#include "sim/body_slices.h"
#include "sim/trace.h"

namespace dw::sim {

std::pair<size_t, size_t> MatchList::at(int64_t step) const {
  const auto [first, last] = std::equal_range(t.begin(), t.end(), step);
  return {static_cast<size_t>(first - t.begin()), static_cast<size_t>(last - t.begin())};
}

uint64_t MatchList::counted_at(int64_t step) const {
  uint64_t n = 0;
  for (const Counted& c : counted) n += c.t == step ? c.matches : 0;
  return n;
}

uint64_t MatchList::counted_total() const {
  uint64_t n = 0;
  for (const Counted& c : counted) n += c.matches;
  return n;
}

Session::Session(Model& model, World& world, SessionOptions options)
    : model_(model), world_(world), options_(std::move(options)) {
  interventions_ = std::move(options_.events);
  options_.events.clear();
  // Over ranks the budget is the run's: each rank's keyframes hold its own modules' part, so each
  // gets an equal share, and K steps as in one process.
  if (options_.ranks && options_.history_bytes > 0)
    options_.history_bytes = std::max<size_t>(1, options_.history_bytes / static_cast<size_t>(options_.ranks->ranks()));
  std::stable_sort(interventions_.begin(), interventions_.end(),
                   [](const Intervention& a, const Intervention& b) { return a.at < b.at; });
  rebuild_runtime();
  head_ = runtime_->initial_state();
  world_on_ = &head_;
  matches_.resize(model_.watches.size());
  stats_.resize(model_.watches.size());
  stats_step_.resize(model_.watches.size());
  take_keyframe();
}

Session::~Session() = default;

void Session::rebuild_runtime() {
  runtime_ = std::make_unique<Runtime>(model_, world_, options_.threads, options_.ranks, options_.partition);
  world_on_ = nullptr;
}

int64_t Session::max_lag() const {
  int64_t lag = 0;
  for (const HostedWatchpoint& h : model_.watches) lag = std::max(lag, h.lag());
  return lag;
}

int64_t Session::decided() const { return latest_ - max_lag(); }

// Every step of every state goes through here: the interventions of the step are applied, and
// the world is told when the state it steps is not the one it stepped last.
State Session::acting_part(const State& keyframe) const {
  State s = simulation_part(keyframe, keyframe.values);
  for (uint32_t w = 0; w < model_.watches.size(); ++w)
    if (!model_.watches[w].watchpoint.program.actions.empty()) s.watches[w] = keyframe.watches[w];
  return s;
}

void Session::step(State& state, StepOutput& out, std::span<const uint8_t> watching) {
  // The programs of this step's time: the model's, or the last replacement made before it.
  for (uint32_t p = 0; p < model_.program_count(); ++p) {
    const HostProgram* program = model_.programs[p].get();
    for (const ProgramVersion& v : program_versions_)
      if (v.program == p && v.from <= state.step) program = v.replacement.get();
    runtime_->use_program(p, *program);
  }
  if (world_on_ != &state) {
    world_.restore(model_, state);
    world_on_ = &state;
  }
  const auto [first, last] =
      std::equal_range(interventions_.begin(), interventions_.end(), Intervention{.at = state.step},
                       [](const Intervention& a, const Intervention& b) { return a.at < b.at; });
  try {
    runtime_->step(state, out, {first, last}, watching);
  } catch (...) {
    world_on_ = nullptr;  // the state is half stepped: the world must measure it again
    throw;
  }
}

void Session::step_head(const StepObserver& observer) {
  if (drained_) throw std::logic_error("a drained session simulates no further step");
  take_keyframe();
  const auto started = std::chrono::steady_clock::now();
  try {
    step(head_, head_out_);
  } catch (const ProgramError& e) {
    if (e.module) failure_ = ProgramFailure{e.step, *e.module, e.what()};
    throw;
  }
  failure_.reset();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  step_seconds_ = step_seconds_ == 0 ? seconds : 0.9 * step_seconds_ + 0.1 * seconds;
  latest_ = head_.step - 1;
  record_output(head_, head_out_, 0, static_cast<uint32_t>(model_.watches.size()));
  if (observer) observer(head_, head_out_);
}

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

void Session::record_output(const State& state, const StepOutput& out, uint32_t first_watch, uint32_t watch_count) {
  for (uint32_t w = first_watch; w < first_watch + watch_count; ++w) {
    const WatchStepOutput& o = out.watches[w];
    stats_[w].stopped = state.watches[w].stopped;
    stats_[w].stop_reason = state.watches[w].stop_reason;
    if (o.observed) {
      stats_[w].add(o.stats);
      stats_step_[w].push_back(out.step);
    }
    keep_matches(w, o.t, out.step, o.matches, o.slots, o.actions);
  }
}

// What a watchpoint keeps of the `matches` it found of watch step t during step `detected`: a
// `count` one their number, the others each group (`slots`, slot_count ids a match) and its
// actions' values.
void Session::keep_matches(uint32_t w, int64_t t, int64_t detected, uint64_t matches, std::span<const ModuleId> slots,
                           std::span<const watch::Value> actions) {
  MatchList& list = matches_[w];
  if (model_.watches[w].action == MatchAction::Count) {
    list.count(t, detected, matches);
    return;
  }
  const uint32_t k = model_.watches[w].watchpoint.program.slot_count();
  list.slots.insert(list.slots.end(), slots.begin(), slots.end());
  list.actions.insert(list.actions.end(), actions.begin(), actions.end());
  list.t.insert(list.t.end(), slots.size() / k, t);
  list.detected.insert(list.detected.end(), slots.size() / k, detected);
}

void Session::drain(const DrainSink& sink) {
  drain_agents(sink);
  for (uint32_t w = 0; w < model_.watches.size(); ++w) {
    WatchState& ws = head_.watches[w];
    if (!ws.detector || ws.stopped) continue;
    const HostedWatchpoint& h = model_.watches[w];
    const uint32_t k = h.watchpoint.program.slot_count();
    ws.detector->set_sink([&](int64_t t, std::span<const ModuleId> ids, std::span<const watch::Value> actions) {
      ws.matches += ids.size() / k;
      keep_matches(w, t, latest_, ids.size() / k, ids, actions);
      if (sink) sink(w, t, ids, actions);
    });
    const watch::DetectorStats before = ws.detector->stats();
    ws.detector->finish();
    // The drain's work, as one more entry of the session's series.
    const watch::DetectorStats& after = ws.detector->stats();
    watch::StepStats drained;
    drained.step = latest_;
    drained.live_by_filled.assign(k + 1, 0);
    for (size_t i = 0; i < after.created_by_filled.size() && i < before.created_by_filled.size(); ++i)
      drained.live_by_filled[i] = after.created_by_filled[i] - before.created_by_filled[i];
    drained.created = after.created - before.created;
    drained.messages = after.messages - before.messages;
    drained.bytes = after.bytes - before.bytes;
    drained.lost = after.lost - before.lost;
    drained.value_messages = after.value_messages - before.value_messages;
    drained.matches = after.matches - before.matches;
    drained.seconds = after.seconds - before.seconds;
    if (drained.created || drained.messages || drained.matches || drained.lost) {
      stats_[w].add(drained);
      stats_step_[w].push_back(latest_);
    }
  }
  drained_ = true;
}

// Agents that wait a hop for their neighbours' values decide the run's last steps too, as replay
// of the run's trace does (watch::DistributedDetector::finish).
void Session::drain_agents(const DrainSink& sink) {
  for (uint32_t w = 0; w < model_.watches.size(); ++w) {
    const HostedWatchpoint& h = model_.watches[w];
    const watch::Program& p = h.watchpoint.program;
    if (!h.runs_on_agents() || p.aggregate_hops == 0) continue;
    for (int64_t f = head_.step - p.agent_delay(); f <= head_.step - 1 - p.extent_plus; ++f) {
      if (f < 0 || head_.watches[w].stopped) continue;
      WatchStepOutput out;
      runtime_->drain_agents(head_, w, f, out);
      if (out.observed) {
        stats_[w].add(out.stats);
        stats_step_[w].push_back(latest_);
      }
      stats_[w].stopped = head_.watches[w].stopped;
      stats_[w].stop_reason = head_.watches[w].stop_reason;
      keep_matches(w, out.t, latest_, out.matches, out.slots, out.actions);
      if (!out.slots.empty() && sink) sink(w, out.t, out.slots, out.actions);
    }
  }
}

// Forgets what was found after step `through` (matches detected later, statistics of later steps).
void Session::truncate_history(int64_t through) {
  for (uint32_t w = 0; w < matches_.size(); ++w) {
    MatchList& list = matches_[w];
    const size_t keep = static_cast<size_t>(std::upper_bound(list.detected.begin(), list.detected.end(), through) -
                                            list.detected.begin());
    const uint32_t k = model_.watches[w].watchpoint.program.slot_count();
    list.t.resize(keep);
    list.detected.resize(keep);
    list.slots.resize(keep * k);
    list.actions.resize(keep * model_.watches[w].watchpoint.program.actions.size());
    std::erase_if(list.counted, [through](const MatchList::Counted& c) { return c.detected > through; });
    std::vector<int64_t>& at = stats_step_[w];
    const size_t entries = static_cast<size_t>(std::upper_bound(at.begin(), at.end(), through) - at.begin());
    std::vector<watch::StepStats> series(
        stats_[w].steps.begin(),
        stats_[w].steps.begin() + static_cast<ptrdiff_t>(std::min(entries, stats_[w].steps.size())));
    at.resize(entries);
    stats_[w] = watch::DetectorStats{};
    for (const watch::StepStats& s : series) stats_[w].add(s);
    stats_[w].stopped = head_.watches[w].stopped;
    stats_[w].stop_reason = head_.watches[w].stop_reason;
  }
}

std::optional<Pause> Session::pause_at(int64_t t, std::optional<uint32_t> to_match) const {
  for (uint32_t w = 0; w < model_.watches.size(); ++w) {
    const bool asked = to_match == w;
    if (model_.watches[w].action != MatchAction::Pause && !asked) continue;
    const MatchList& list = matches_[w];
    const auto [first, last] = list.at(t);
    if (first == last) continue;
    const size_t k = model_.watches[w].watchpoint.program.slot_count();
    return Pause{w,
                 asked,
                 t,
                 list.detected[first],
                 {list.slots.begin() + static_cast<ptrdiff_t>(first * k),
                  list.slots.begin() + static_cast<ptrdiff_t>((first + 1) * k)},
                 last - first};
  }
  return std::nullopt;
}

std::optional<Pause> Session::run_until(int64_t end, const StepObserver& observer, const Control& control,
                                        std::optional<uint32_t> to_match) {
  const int64_t target = end - 1;
  const int64_t limit = std::max(options_.end, end);  // steps simulated ahead stay below it
  const int64_t lag = max_lag();
  const int64_t from = current_;
  while (current_ < target) {
    const int64_t t = current_ + 1;
    // The cursor moves onto a step once every watchpoint has decided it, or the end stops the look ahead.
    const int64_t need = std::max(t, std::min(t + lag, limit - 1));
    while (latest_ < need) {
      if (control.stopped()) return std::nullopt;
      step_head(observer);
    }
    current_ = t;
    if (control.progress) control.progress(current_ - from, target - from);
    if (auto pause = pause_at(t, to_match)) return pause;
    if (control.stopped()) return std::nullopt;
  }
  return std::nullopt;
}

void Session::decide(int64_t t, const StepObserver& observer, const Control& control) {
  while (latest_ < t + max_lag() && !control.stopped()) step_head(observer);
}

bool Session::seek(int64_t t, const Control& control) {
  if (t < -1 || t > latest_ || (t < latest_ && !has_history())) return false;
  if (t < latest_ && !materialize(t, control)) return false;
  current_ = t;
  return true;
}

// Brings view_ to the full state after step t (< latest_): on from where it is when that is
// nearer, else from the keyframe at or before t.
bool Session::materialize(int64_t t, const Control& control) {
  const int64_t at = view_valid_ ? view_.step - 1 : -2;
  if (at == t) return true;
  if (!has_history()) return false;
  const size_t index = t < 0 ? 0 : std::min(static_cast<size_t>(t / interval_), keyframes_.size() - 1);
  const int64_t keyframe_step = static_cast<int64_t>(index) * interval_;
  if (!(at < t && at >= keyframe_step)) {
    view_ = keyframes_[index];
    restore_bodies(view_, index);
    view_out_ = StepOutput{};
    view_valid_ = true;
    if (world_on_ == &view_) world_on_ = nullptr;
  }
  const int64_t from = view_.step;
  while (view_.step <= t) {
    if (control.stopped()) return false;
    step(view_, view_out_);
    if (control.progress) control.progress(view_.step - from, t + 1 - from);
  }
  return true;
}

const State& Session::state() {
  // Without history only the latest state exists.
  if (current_ == latest_ || !materialize(current_, {})) return head_;
  return view_;
}

std::span<const uint8_t> Session::seen_present() {
  const State& s = state();
  const StepOutput& out = &s == &head_ ? head_out_ : view_out_;
  return current_ < 0 ? std::span<const uint8_t>(s.present) : std::span<const uint8_t>(out.present);
}

const NeighborGraph& Session::seen_graph() {
  const State& s = state();
  const StepOutput& out = &s == &head_ ? head_out_ : view_out_;
  return current_ < 0 ? *s.graph : *out.graph;
}

std::string Session::push_moves_nothing(ModuleId m) {
  const Bodies& b = state().bodies;
  if (m >= b.cluster_of.size()) return {};
  const std::string who = "module " + std::to_string(m), when = " at step " + std::to_string(current_);
  if (b.moving(m))
    return who + " is making a lattice move" + when + ": it glides along its path whatever pushes it, so the push " +
           "moves nothing";
  const uint32_t c = b.cluster_of[m];
  if (c != kNoCluster && b.clusters[c].anchored)
    return who + " is latched to the ground" + when + " (its cluster of " + std::to_string(b.clusters[c].count) +
           " modules is anchored): the push moves nothing unless a program's move frees it in the next step";
  return {};
}

std::string Session::intervene(Intervention i) {
  i.at = current_ + 1;
  i.scheduled = false;
  if (i.module >= model_.module_count())
    return "module " + std::to_string(i.module) + " is not in the ensemble (ids 0.." +
           std::to_string(static_cast<int64_t>(model_.module_count()) - 1) + ")";
  if (i.kind == Intervention::Kind::Set && (i.column < 0 || static_cast<uint32_t>(i.column) >= model_.variable_count()))
    return "no program has that variable";
  if (i.kind == Intervention::Kind::Push && head_.bodies.empty())
    return "push needs bodies, and this scenario has no physics";
  {  // a module removed keeps its variables and body where they were, read by nothing: a set or
     // push on it would change nothing the run shows, and the intervention would be kept for naught
    const State& now = state();
    const bool queued = std::any_of(interventions_.begin(), interventions_.end(), [&](const Intervention& o) {
      return o.at == i.at && o.kind == Intervention::Kind::Remove && o.module == i.module;
    });
    if (std::string problem = empty_cell_problem(model_.lattice, i.module, i.kind); !problem.empty()) return problem;
    if (queued || (i.module < now.present.size() && !now.present[i.module]))
      return "module " + std::to_string(i.module) + " is already gone at step " + std::to_string(i.at) +
             ": there is nothing to " + intervention_name(i.kind);
  }
  if (current_ < latest_ && !has_history()) return "the session keeps no history to branch from";
  if (current_ < latest_) branch_here();
  drop_changes_after(i.at);
  const auto after = std::upper_bound(interventions_.begin(), interventions_.end(), i,
                                      [](const Intervention& a, const Intervention& b) { return a.at < b.at; });
  interventions_.insert(after, i);
  return {};
}

void Session::branch_here() {
  materialize(current_, {});
  head_ = std::move(view_);
  head_out_ = std::move(view_out_);
  view_valid_ = false;
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

// What was made in a dropped future goes with it; the scenario's schedule stays.
void Session::drop_changes_after(int64_t at) {
  failure_.reset();  // the steps after `at` will run otherwise
  std::erase_if(interventions_, [&](const Intervention& x) { return x.at > at && !x.scheduled; });
  std::erase_if(program_versions_, [&](const ProgramVersion& v) { return v.from > at; });
}

std::string Session::replace_programs(std::vector<Replacement> replacements) {
  for (const Replacement& r : replacements) {
    if (r.program >= model_.program_count()) return "there is no program " + std::to_string(r.program);
    if (!same_variables(*r.with, *model_.programs[r.program]))
      return std::string(r.with->name()) +
             " now declares other variables than the run has; a program replaced in a run must keep them (load the "
             "scenario again instead)";
  }
  if (current_ < latest_ && !has_history()) return "the session keeps no history to branch from";
  if (current_ < latest_) branch_here();
  const int64_t from = current_ + 1;
  drop_changes_after(from);
  for (Replacement& r : replacements) program_versions_.push_back({from, r.program, std::move(r.with)});
  return {};
}

int Session::watch_index(std::string_view name) const {
  for (uint32_t w = 0; w < model_.watches.size(); ++w)
    if (model_.watches[w].watchpoint.name == name) return static_cast<int>(w);
  return -1;
}

std::optional<uint32_t> Session::set_watch(HostedWatchpoint watch, const Control& control) {
  // The new watchpoint goes in last and is evaluated alone over the history, from the first
  // keyframe, its state copied into every keyframe on the way; only then does it take its place.
  if (!has_history()) return std::nullopt;
  const int replaces = watch_index(watch.watchpoint.name);
  const uint32_t w = static_cast<uint32_t>(model_.watches.size());
  if (!watch.watchpoint.program.actions.empty() ||
      (replaces >= 0 && !model_.watches[static_cast<size_t>(replaces)].watchpoint.program.actions.empty())) {
    // Its actions change the states themselves (docs/design.md §4b): the history is simulated again.
    if (replaces >= 0) {
      model_.watches[static_cast<size_t>(replaces)] = std::move(watch);
    } else {
      model_.watches.push_back(std::move(watch));
      matches_.emplace_back();
      stats_.emplace_back();
      stats_step_.emplace_back();
    }
    rebuild_runtime();
    resimulate();
    return replaces >= 0 ? static_cast<uint32_t>(replaces) : w;
  }
  model_.watches.push_back(std::move(watch));
  rebuild_runtime();
  matches_.emplace_back();
  stats_.emplace_back();
  stats_step_.emplace_back();
  auto undo = [&] {
    model_.watches.pop_back();
    matches_.pop_back();
    stats_.pop_back();
    stats_step_.pop_back();
    rebuild_runtime();
  };

  State s = acting_part(keyframes_[0]);
  restore_bodies(s, 0);
  s.watches.push_back(runtime_->initial_watch_state(w));
  std::vector<WatchState> at_keyframe{s.watches[w]};  // its state at keyframes_[i]
  size_t added = state_bytes(State{.watches = {at_keyframe[0]}});
  std::vector<uint8_t> watching(w + 1, 0);
  watching[w] = 1;
  StepOutput out;
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
    if (control.stopped()) {
      undo();
      return std::nullopt;
    }
    try {
      step(s, out, watching);
    } catch (...) {
      undo();
      throw;
    }
    world_on_ = nullptr;  // `s` is a local
    record_output(s, out, w, 1);
    if (control.progress) control.progress(s.step, latest_ + 1);
  }
  for (size_t i = 0; i < keyframes_.size(); ++i) keyframes_[i].watches.push_back(std::move(at_keyframe[i]));
  head_.watches.push_back(std::move(s.watches[w]));
  view_valid_ = false;

  if (replaces >= 0) {
    // Into the old one's place: the other watchpoints keep their indices.
    const auto r = static_cast<size_t>(replaces);
    model_.watches[r] = std::move(model_.watches.back());
    model_.watches.pop_back();
    auto move_last = [r](auto& v) {
      v[r] = std::move(v.back());
      v.pop_back();
    };
    move_last(matches_);
    move_last(stats_);
    move_last(stats_step_);
    move_last(head_.watches);
    for (State& k : keyframes_) move_last(k.watches);
    rebuild_runtime();
    recount_history();
    look_ahead({});
    return static_cast<uint32_t>(replaces);
  }
  recount_history();
  look_ahead({});
  return w;
}

// A new watchpoint may have a longer lag: the current step is decided again, as far as the end allows.
void Session::look_ahead(const StepObserver& observer) {
  const int64_t need = std::min(current_ + max_lag(), options_.end - 1);
  while (latest_ < need) step_head(observer);
}

bool Session::remove_watch(std::string_view name) {
  const int found = watch_index(name);
  if (found < 0) return false;
  const auto w = static_cast<ptrdiff_t>(found);
  const bool acted = !model_.watches[static_cast<size_t>(w)].watchpoint.program.actions.empty();
  model_.watches.erase(model_.watches.begin() + w);
  matches_.erase(matches_.begin() + w);
  stats_.erase(stats_.begin() + w);
  stats_step_.erase(stats_step_.begin() + w);
  head_.watches.erase(head_.watches.begin() + w);
  for (State& k : keyframes_) k.watches.erase(k.watches.begin() + w);
  view_valid_ = false;
  rebuild_runtime();
  recount_history();
  if (acted) resimulate();
  return true;
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
  for (uint32_t w = 0; w < model_.watches.size(); ++w) {
    matches_[w] = {};
    stats_[w] = {};
    stats_step_[w].clear();
  }
  latest_ = current_ = -1;
  view_valid_ = false;
  failure_.reset();
  take_keyframe();
  while (latest_ < latest) step_head({});
  current_ = latest_;
  seek(current);
}

std::vector<uint64_t> Session::match_counts(uint32_t w, int64_t from, int64_t to) const {
  std::vector<uint64_t> counts(static_cast<size_t>(std::max<int64_t>(0, to - from + 1)), 0);
  const MatchList& list = matches_[w];
  for (const MatchList::Counted& c : list.counted)
    if (c.t >= from && c.t <= to) counts[static_cast<size_t>(c.t - from)] += c.matches;
  const size_t first = list.at(from).first;
  for (size_t i = first; i < list.size() && list.t[i] <= to; ++i) ++counts[static_cast<size_t>(list.t[i] - from)];
  return counts;
}

std::optional<std::vector<int64_t>> Session::series(ModuleId m, int column, int64_t from, int64_t to,
                                                    const Control& control) {
  auto rows = module_series(m, from, to, control);
  if (!rows) return std::nullopt;
  const size_t v = model_.variable_count();
  std::vector<int64_t> values;
  for (size_t i = static_cast<size_t>(column); i < rows->size(); i += v) values.push_back((*rows)[i]);
  return values;
}

std::optional<std::vector<int64_t>> Session::module_series(ModuleId m, int64_t from, int64_t to,
                                                           const Control& control) {
  std::vector<int64_t> values;
  if (from > to || !has_history()) return values;
  // The values depend on the watchpoints with actions alone: the others are not stepped.
  const size_t index = std::min(static_cast<size_t>(std::max<int64_t>(0, from) / interval_), keyframes_.size() - 1);
  State s = acting_part(keyframes_[index]);
  restore_bodies(s, index);
  const std::vector<uint8_t> none(model_.watches.size() + 1, 0);
  StepOutput out;
  const size_t v = model_.variable_count();
  while (s.step <= to) {
    if (control.stopped()) return std::nullopt;
    step(s, out, none);
    world_on_ = nullptr;
    if (s.step - 1 >= from) {
      const auto row = s.values.begin() + static_cast<std::ptrdiff_t>(size_t{m} * v);
      values.insert(values.end(), row, row + static_cast<std::ptrdiff_t>(v));
    }
  }
  return values;
}

std::string Session::record(std::ostream& out, const Control& control) {
  if (!has_history()) return "the session keeps no history to record";
  State s = acting_part(keyframes_[0]);
  restore_bodies(s, 0);
  const std::vector<uint8_t> none(model_.watches.size() + 1, 0);
  StepOutput step_out;
  TraceWriter writer(out, model_.universe, interventions_, specs_of(model_.watches));
  while (s.step <= latest_) {
    if (control.stopped()) return "cancelled";
    step(s, step_out, none);
    world_on_ = nullptr;
    writer.write(observed_frame(model_, s, step_out));
    if (control.progress) control.progress(s.step, latest_ + 1);
  }
  out.flush();
  return out ? std::string{} : "writing the trace failed";
}

}  // namespace dw::sim
