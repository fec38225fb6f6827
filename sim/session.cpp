// The session's core (docs/design.md §7): stepping the head, moving the cursor (run, seek,
// decide), the states and series it shows, and the record of its history. The keyframes are in
// session_history.cpp, the watchpoints in session_watches.cpp, the interventions and reloaded
// programs in session_interventions.cpp.
#include "sim/session.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "sim/body_slices.h"
#include "sim/run_outputs.h"

namespace dw::sim {

Session::Session(const Model& model, World& world, SessionOptions options)
    : model_(model), world_(world), options_(std::move(options)), watches_(model.watches) {
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
  take_keyframe();
}

// Every member but the runtime, which is made afresh over `world` (the world is told the state it
// steps before its first step: world_on_), and the spare keyframes' storage (nothing of the history).
Session::Session(const Session& other, World& world, unsigned threads)
    : model_(other.model_),
      world_(world),
      options_(other.options_),
      watches_(other.watches_),
      interventions_(other.interventions_),
      program_versions_(other.program_versions_),
      failure_(other.failure_),
      head_(other.head_),
      drained_(other.drained_),
      end_drained_(other.end_drained_),
      before_end_drain_(other.before_end_drain_),
      end_drain_matches_(other.end_drain_matches_),
      head_out_(other.head_out_),
      latest_(other.latest_),
      current_(other.current_),
      view_(other.view_),
      view_out_(other.view_out_),
      view_valid_(other.view_valid_),
      measured_poses_(other.measured_poses_),
      measured_for_(other.measured_for_),
      keyframes_(other.keyframes_),
      body_slices_(other.body_slices_),
      step_seconds_(other.step_seconds_),
      interval_(other.interval_),
      history_bytes_(other.history_bytes_),
      run_charges_(other.run_charges_),
      series_entries_(other.series_entries_) {
  if (options_.ranks) throw std::logic_error("a session over ranks is not copied");
  options_.threads = threads;
  rebuild_runtime();
}

Session::~Session() = default;

void Session::rebuild_runtime() {
  HostedWatches hosted = watches_.hosted();
  hosted.run_budget = options_.run_live_budget;
  runtime_ = std::make_unique<Runtime>(model_, std::move(hosted), world_, options_.threads, options_.ranks,
                                       options_.partition);
  world_on_ = nullptr;
}

int64_t Session::max_lag() const {
  int64_t lag = 0;
  for (uint32_t w = 0; w < watches_.size(); ++w) lag = std::max(lag, watches_[w].hosted.lag());
  return lag;
}

int64_t Session::decided() const { return end_drained_ ? latest_ : latest_ - max_lag(); }

// Every step of every state goes through here: the interventions of the step are applied, and
// the world is told when the state it steps is not the one it stepped last.
State Session::acting_part(const State& keyframe) const {
  State s = simulation_part(keyframe, keyframe.values);
  for (uint32_t w = 0; w < watches_.size(); ++w)
    if (!watches_[w].hosted.watchpoint.program.actions.empty()) s.watches[w] = keyframe.watches[w];
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
  forget_end_drain();  // past the end, the watchpoints decide those steps themselves
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
  if (const uint64_t charged = runtime_->charged(); charged != (run_charges_.empty() ? 0 : run_charges_.back().second))
    run_charges_.push_back({latest_, charged});
  record_output(head_, head_out_, 0, watches_.size());
  if (observer) observer(head_, head_out_);
  drain_at_end();
}

std::optional<Pause> Session::pause_at(int64_t t, std::optional<uint32_t> to_match) const {
  for (uint32_t w = 0; w < watches_.size(); ++w) {
    const bool asked = to_match == w;
    if (watches_[w].hosted.action != MatchAction::Pause && !asked) continue;
    const MatchList& list = watches_[w].matches;
    const auto [first, last] = list.at(t);
    if (first == last) continue;
    if (!asked && end_drained_ && w < before_end_drain_.size() && first >= before_end_drain_[w].first)
      continue;  // the end's drain pauses no run
    const size_t k = watches_[w].hosted.watchpoint.program.slot_count();
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

std::optional<Pose> Session::measured_pose(ModuleId m, const Control& control) {
  // Before step 0 the graph shown is the initial state's, measured from its own poses.
  if (current_ < 0) {
    const State& s = state();
    return s.bodies.empty() ? std::nullopt : std::optional(s.bodies.poses[m]);
  }
  if (measured_for_ != current_) {
    if (!has_history() || !materialize(current_ - 1, control)) return std::nullopt;
    measured_poses_ = view_.bodies.poses;
    measured_for_ = current_;
  }
  if (measured_poses_.empty()) return std::nullopt;
  return measured_poses_[m];
}

std::optional<std::vector<int64_t>> Session::series(ModuleId m, int column, int64_t from, int64_t to,
                                                    const Control& control, std::vector<uint8_t>* present) {
  auto rows = module_series(m, from, to, control, present);
  if (!rows) return std::nullopt;
  const size_t v = model_.variable_count();
  std::vector<int64_t> values;
  for (size_t i = static_cast<size_t>(column); i < rows->size(); i += v) values.push_back((*rows)[i]);
  return values;
}

std::optional<std::vector<int64_t>> Session::module_series(ModuleId m, int64_t from, int64_t to, const Control& control,
                                                           std::vector<uint8_t>* present) {
  std::vector<int64_t> values;
  if (from > to || !has_history()) return values;
  // The values depend on the watchpoints with actions alone: the others are not stepped.
  const size_t index = std::min(static_cast<size_t>(std::max<int64_t>(0, from) / interval_), keyframes_.size() - 1);
  State s = acting_part(keyframes_[index]);
  restore_bodies(s, index);
  const std::vector<uint8_t> none(watches_.size() + 1, 0);
  StepOutput out;
  const size_t v = model_.variable_count();
  while (s.step <= to) {
    if (control.stopped()) return std::nullopt;
    step(s, out, none);
    world_on_ = nullptr;
    if (s.step - 1 >= from) {
      const auto row = s.values.begin() + static_cast<std::ptrdiff_t>(size_t{m} * v);
      values.insert(values.end(), row, row + static_cast<std::ptrdiff_t>(v));
      if (present) present->push_back(s.present[m]);
    }
  }
  return values;
}

std::string Session::record(std::ostream& out, const Control& control) {
  if (!has_history()) return "the session keeps no history to record";
  State s = acting_part(keyframes_[0]);
  restore_bodies(s, 0);
  const std::vector<uint8_t> none(watches_.size() + 1, 0);
  StepOutput step_out;
  // As a run's --record writes it: its header lists the branch's interventions and the watchpoints.
  RunOutputs outputs(watches_.hosted(), nullptr);
  outputs.record(out, model_.universe, interventions_);
  while (s.step <= latest_) {
    if (control.stopped()) return "cancelled";
    step(s, step_out, none);
    world_on_ = nullptr;
    outputs.record_frame(observed_frame(model_, s, step_out));
    if (control.progress) control.progress(s.step, latest_ + 1);
  }
  out.flush();
  return out ? std::string{} : "writing the trace failed";
}

}  // namespace dw::sim
