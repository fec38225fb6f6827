#include "sim/watch_hosting.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "sim/whole_over_ranks.h"
#include "watch/agent_step.h"
#include "watch/make_detector.h"

namespace dw::sim {
namespace {

// The step's statistics are those of all ranks, and so is a stop: with the reason of the first
// rank that gave one. In one process the outcome is the whole.
void add_up_over_ranks(RankExchange* ranks, watch::AgentStepOutcome& outcome) {
  if (ranks == nullptr) return;
  watch::StepStats& st = outcome.stats;
  std::vector<uint64_t> sums = st.live_by_filled;
  sums.insert(sums.end(), {st.live, st.created, st.messages, st.bytes, st.matches, outcome.over_budget,
                           st.value_messages, outcome.wanted});
  ranks->sum(sums);
  const size_t n = st.live_by_filled.size();
  std::copy(sums.begin(), sums.begin() + static_cast<ptrdiff_t>(n), st.live_by_filled.begin());
  st.live = sums[n], st.created = sums[n + 1], st.messages = sums[n + 2], st.bytes = sums[n + 3];
  st.matches = sums[n + 4];
  st.value_messages = sums[n + 6];
  outcome.wanted = sums[n + 7];
  if (sums[n + 5] == 0) return;
  outcome.over_budget = true;
  for (const std::span<const std::byte> why : ranks->all_gather(std::as_bytes(std::span(outcome.stop_reason))))
    if (!why.empty()) {
      outcome.stop_reason.assign(reinterpret_cast<const char*>(why.data()), why.size());
      break;
    }
}

// The order the run's budget charges the watchpoints in: those with actions first, whose stops
// change the simulation (a re-simulation steps them alone, and they must stop alike), then the
// others, each in position order.
std::vector<uint32_t> charging_order(const HostedWatches& watches) {
  std::vector<uint32_t> order;
  for (int acting = 1; acting >= 0; --acting)
    for (uint32_t w = 0; w < watches.size(); ++w)
      if (!watches[w].watchpoint.program.actions.empty() == bool(acting)) order.push_back(w);
  return order;
}

std::vector<uint64_t> own_budgets(const HostedWatches& watches, std::span<const uint32_t> order) {
  std::vector<uint64_t> own;
  for (uint32_t w : order) own.push_back(watches[w].options.live_budget);
  return own;
}

}  // namespace

// A thread's PatternMatcher outbox: each copy goes into the lane of its receiver's block.
struct WatchHosting::Lanes final : watch::PatternMatcherOutbox {
  watch::RecordBuffer* row;  // this thread's lanes, one per receiving block
  uint32_t block_shift;
  void send(uint32_t, std::span<const uint32_t> to, const std::byte* pm, uint32_t bytes) override {
    // One record per run of receivers in the same block.
    for (size_t i = 0, j; i < to.size(); i = j) {
      const uint32_t block = to[i] >> block_shift;
      for (j = i + 1; j < to.size() && to[j] >> block_shift == block; ++j) {
      }
      row[block].append(to.subspan(i, j - i), pm, bytes);
    }
  }
};

watch::Frame make_frame(const Model& model, int64_t step, std::span<const int64_t> values,
                        std::span<const uint8_t> present, const std::shared_ptr<const NeighborGraph>& graph,
                        uint32_t first_module) {
  watch::Frame frame;
  frame.step = step;
  frame.present = present;
  frame.values = values;
  frame.first_module = first_module;
  frame.nbr_begin = graph->begin;
  frame.nbrs = graph->ids;
  frame.variable_count = model.variable_count();
  frame.topology = graph;
  return frame;
}

std::string why_not_over_ranks(std::span<const HostedWatchpoint> watches) {
  for (const HostedWatchpoint& w : watches)
    if (!w.runs_on_agents() && w.watchpoint.program.slot_count() > 0)
      return "watchpoint '" + w.watchpoint.name + "' is " +
             (w.algorithm == watch::Algorithm::Centralized ? "centralized" : "read over simultaneous states") +
             ": its detector observes the whole ensemble in one place, which no rank holds; over ranks a "
             "watchpoint runs on the modules' agents (algorithm = \"distributed\", states = \"consistent\"; "
             "or --algorithm distributed --states consistent)";
  return {};
}

WatchHosting::WatchHosting(const Model& model, HostedWatches watches, const BlockPlacement& placement, unsigned threads,
                           RankExchange* ranks)
    : model_(model),
      watches_(std::move(watches)),
      placement_(placement),
      threads_(threads),
      ranks_(ranks),
      contexts_(threads),
      arriving_(threads),
      charging_order_(charging_order(watches_)),
      charged_at_(watches_.size()),
      run_budget_(watches_.run_budget, own_budgets(watches_, charging_order_)),
      published_(threads, std::vector<uint64_t>(watches_.size())) {
  for (uint32_t i = 0; i < charging_order_.size(); ++i) {
    charged_at_[charging_order_[i]] = i;
    acting_count_ += watches_[charging_order_[i]].watchpoint.program.actions.empty() ? 0 : 1;
  }
  for (std::vector<watch::AgentContext>& contexts : contexts_)
    for (const HostedWatchpoint& w : watches_) {
      // Each thread may use the whole budget; whether the step went over it is decided on the
      // threads' sum afterwards (finish_distributed), so the stop never depends on the thread count.
      contexts.emplace_back(w.watchpoint.program, w.options.optimizations, w.options.live_budget);
    }
  const size_t lanes = size_t{threads} * placement.blocks();
  for (const HostedWatchpoint& w : watches_) {
    snapshot_.push_back(w.runs_on_agents() && watch::reads_step_snapshot(w.watchpoint.program));
    far_lists_.push_back(ranks_ && w.runs_on_agents() && watch::reads_far_lists(w.watchpoint.program));
    columns_.push_back(watch::variable_columns(w.watchpoint.program, model.universe));
    sending_.emplace_back(w.runs_on_agents() ? lanes : 0);
  }
}

WatchState WatchHosting::initial_state(uint32_t w) const {
  const HostedWatchpoint& h = watches_[w];
  WatchState ws;
  if (!h.runs_on_agents()) {
    ws.detector = watch::make_detector(h.algorithm, h.watchpoint, model_.universe, h.options, nullptr);
    ws.detector->stats().max_steps = 0;  // the run keeps its own series
  } else {
    // An aggregate reads neighbours, which may be another rank's: its agents keep every module's
    // history, the others' filled as the step ends (share_neighbor_values).
    const bool whole = ranks_ && !h.watchpoint.program.aggregates.empty();
    ws.agents.emplace(h.watchpoint.program, h.options.optimizations.temporal_spans,
                      whole ? 0 : placement_.first_module(),
                      whole ? model_.module_count() : placement_.module_window());
    if (h.watchpoint.program.reads_id) ws.agents->set_module_ids(model_.universe.module_ids);  // id() (§4c)
    ws.in_flight.resize(size_t{threads_} * placement_.blocks());
  }
  return ws;
}

bool WatchHosting::observes(uint32_t w, std::span<const uint8_t> watching) const {
  return watching.empty() || watching[w] || !watches_[w].watchpoint.program.actions.empty();
}

void WatchHosting::begin_step(State& state, std::span<const uint8_t> watching, std::span<const int64_t> next_values) {
  draining_ = false;  // a session steps on past the drain at its end: steps charge the run's budget again
  agent_watches_.clear();
  run_budget_.begin_step(others_, acting_count_);
  for (std::vector<uint64_t>& thread : published_) std::fill(thread.begin(), thread.end(), 0);
  for (uint32_t w = 0; w < size(); ++w) {
    if (!watches_[w].runs_on_agents() || state.watches[w].stopped) continue;
    if (!observes(w, watching)) continue;
    agent_watches_.push_back(w);
  }
  gather_whole_graph(state);
  for (uint32_t w : agent_watches_) {
    for (watch::RecordBuffer& lane : sending_[w]) lane.clear();  // a step that failed may have filled some
    state.watches[w].agents->begin_record(
        make_frame(model_, state.step, next_values, state.present, agent_graph(w, state), placement_.first_module()));
  }
}

// Over ranks, a rank holds the neighbour lists of its window only (docs/design.md §12); within() and
// component() read lists further out, so their agents are lent every module's, gathered from the
// owners whenever any rank's window changed (a static lattice's once).
void WatchHosting::gather_whole_graph(const State& state) {
  const bool wanted =
      std::any_of(agent_watches_.begin(), agent_watches_.end(), [&](uint32_t w) { return far_lists_[w] != 0; });
  if (!wanted || !any_rank(ranks_, whole_of_ != state.graph)) return;
  whole_graph_ = gather_graph(*ranks_, placement_, *state.graph);
  whole_of_ = state.graph;
}

const std::shared_ptr<const NeighborGraph>& WatchHosting::agent_graph(uint32_t w, const State& state) const {
  return far_lists_[w] ? whole_graph_ : state.graph;
}

std::vector<WatchHosting::SendingGraph> WatchHosting::sending_graphs(const State& state) const {
  std::vector<SendingGraph> graphs;
  for (uint32_t w : agent_watches_) {
    const watch::AgentHistory& history = state.watches[w].agents->history();
    const int64_t f = state.step - watches_[w].watchpoint.program.agent_delay();
    if (auto owner = history.graph_owner(f)) graphs.push_back({std::move(owner), history.graph(f)});
  }
  return graphs;
}

void WatchHosting::start_thread(unsigned thread, int64_t step) {
  for (uint32_t w : agent_watches_)
    watch::start_agent_step(contexts_[thread][w], step - watches_[w].watchpoint.program.agent_delay());
}

// One block of agents for each agent watch, in the order that keeps the block's agents in cache:
// each records its module's state at t and decides its own leaves, then the PatternMatchers sent
// to the block arrive, then every agent starts its own (watch/agent_step.h).
void WatchHosting::run_block(unsigned thread, uint32_t block, State& state, std::span<const int64_t> next_values) {
  for (uint32_t w : agent_watches_) {
    const watch::Program& program = watches_[w].watchpoint.program;
    WatchState& ws = state.watches[w];
    const uint32_t begin = placement_.block_begin(block), end = placement_.block_begin(block + 1);
    const watch::Frame frame =
        make_frame(model_, state.step, next_values, state.present, agent_graph(w, state), placement_.first_module());
    if (snapshot_[w]) {  // decided in run_late_block, once every block has recorded the step
      ws.agents->record_history(frame, begin, end, columns_[w]);
      continue;
    }
    ws.agents->record(frame, begin, end, program, columns_[w]);
    const int64_t f = state.step - program.agent_delay();
    if (f >= 0) step_block_agents(thread, block, w, ws, f);
  }
}

bool WatchHosting::late_agents() const {
  return std::any_of(agent_watches_.begin(), agent_watches_.end(), [&](uint32_t w) { return snapshot_[w] != 0; });
}

void WatchHosting::run_late_block(unsigned thread, uint32_t block, State& state) {
  for (uint32_t w : agent_watches_) {
    if (!snapshot_[w]) continue;
    const watch::Program& program = watches_[w].watchpoint.program;
    WatchState& ws = state.watches[w];
    ws.agents->work_out(program, state.step, placement_.block_begin(block), placement_.block_begin(block + 1));
    const int64_t f = state.step - program.agent_delay();
    if (f >= 0) step_block_agents(thread, block, w, ws, f);
  }
}

// Detector step f of one block's agents: the PatternMatchers sent to the block arrive, then each
// present agent starts its own; what they send goes into this thread's lanes.
void WatchHosting::step_block_agents(unsigned thread, uint32_t block, uint32_t w, WatchState& ws, int64_t f) {
  const uint32_t blocks = placement_.blocks();
  Lanes out;
  out.row = sending_[w].data() + size_t{thread} * blocks;
  out.block_shift = placement_.owners().block_shift;
  arriving_[thread].clear();
  for (unsigned from = 0; from < threads_; ++from)
    arriving_[thread].push_back(&ws.in_flight[size_t{from} * blocks + block]);
  const watch::RunCharge run{&run_budget_, charged_at_[w], &published_[thread][w]};
  watch::step_agents(*ws.agents, placement_.block_begin(block), placement_.block_begin(block + 1), f, arriving_[thread],
                     contexts_[thread][w], out, draining_ ? watch::RunCharge{} : run);
}

// The watchpoints decide in the run budget's charging order (each one's outcome is its own, in
// out[w], whatever the order).
void WatchHosting::finish_step(State& state, std::span<WatchStepOutput> out, std::span<const uint8_t> watching,
                               std::span<const std::vector<ArrivedLane>> arrived) {
  charged_ = 0;
  passed_ = false;
  step_ = state.step;
  for (uint32_t i = 0; i < charging_order_.size(); ++i) {
    const uint32_t w = charging_order_[i];
    if (i == acting_count_ && others_) {
      charged_ = *others_;
      passed_ = run_budget_.limit() != 0 && charged_ > run_budget_.limit();
    }
    if (state.watches[w].stopped || !observes(w, watching)) continue;
    if (watches_[w].runs_on_agents())
      finish_distributed(w, state, out[w], state.step - watches_[w].watchpoint.program.agent_delay(),
                         w < arrived.size() ? std::span(arrived[w]) : std::span<const ArrivedLane>{}, true);
    else observe_detector(w, state, out[w]);
    WatchStepOutput& o = out[w];
    state.watches[w].matches += o.matches;
    sort_matches(w, o);
  }
  others_.reset();
}

namespace {
constexpr std::string_view kRaisesRunBudget = "(--max-live-all raises it)";
}  // namespace

std::string over_run_budget(bool already, uint64_t limit, std::string_view when) {
  return std::string(already ? "with the watchpoints charged before it, which passed"
                             : "with the watchpoints charged before it, more than") +
         " the whole run's budget of " + std::to_string(limit) + " live PatternMatchers " + std::string(when) + " " +
         std::string(kRaisesRunBudget);
}

std::string stop_text(const std::string& reason, std::string_view own_budget) {
  std::string text = reason + "; the matches found before are kept";
  if (reason.find(kRaisesRunBudget) == std::string::npos) text += " (" + std::string(own_budget) + " sets the budget)";
  return text;
}

std::string WatchHosting::run_budget_verdict(uint32_t w, uint64_t wanted) {
  const uint64_t limit = run_budget_.limit();
  const bool before = passed_;
  charged_ += watch::RunBudget::charge(wanted, watches_[w].options.live_budget);
  passed_ = limit != 0 && (passed_ || charged_ > limit);
  if (!passed_) return {};
  return over_run_budget(before, limit, "at step " + std::to_string(step_));
}

void WatchHosting::stop(WatchState& ws, uint32_t w, std::string why) {
  ws.stopped = true;
  ws.stop_reason = std::move(why);
  // A stopped watch lets go of its agents and PatternMatchers.
  ws.agents.reset();
  ws.in_flight = {};
  for (watch::RecordBuffer& lane : sending_[w]) lane = {};
}

void WatchHosting::drain_begin(uint32_t w) {
  for (watch::RecordBuffer& lane : sending_[w]) lane.clear();
  agent_watches_ = {w};  // what a batch between ranks carries: this watch's PatternMatchers alone
  draining_ = true;
}

// The thread's share of this rank's blocks (the t-th of equal runs), each block's agents made
// ready for detector step f from the history they hold, then stepped.
void WatchHosting::drain_blocks(unsigned thread, uint32_t w, int64_t f, State& state) {
  const watch::Program& program = watches_[w].watchpoint.program;
  WatchState& ws = state.watches[w];
  watch::start_agent_step(contexts_[thread][w], f);
  const uint64_t budget = run_budget_.own(charged_at_[w]);  // as the run's budget may have left it lower
  contexts_[thread][w].live_limit = budget == 0 ? UINT64_MAX : budget;
  const std::span<const uint32_t> own = placement_.own_blocks();
  const size_t n = own.size();
  for (size_t i = thread * n / threads_; i < (thread + 1) * n / threads_; ++i) {
    const uint32_t block = own[i];
    ws.agents->prepare(program, f, placement_.block_begin(block), placement_.block_begin(block + 1));
    step_block_agents(thread, block, w, ws, f);
  }
}

// Gathers the threads' matches and statistics; the PatternMatchers sent become those in flight.
void WatchHosting::drain_finish(State& state, uint32_t w, int64_t f, WatchStepOutput& out,
                                std::span<const std::vector<ArrivedLane>> arrived) {
  finish_distributed(w, state, out, f, w < arrived.size() ? std::span(arrived[w]) : std::span<const ArrivedLane>{});
  state.watches[w].matches += out.matches;
  sort_matches(w, out);
}

void WatchHosting::finish_distributed(uint32_t w, State& state, WatchStepOutput& out, int64_t f,
                                      std::span<const ArrivedLane> arrived, bool whole_run) {
  const HostedWatchpoint& hosted = watches_[w];
  const watch::Program& program = hosted.watchpoint.program;
  WatchState& ws = state.watches[w];
  const uint32_t k = program.slot_count();
  for (size_t lane = 0; lane < ws.in_flight.size(); ++lane) {
    std::swap(ws.in_flight[lane], sending_[w][lane]);
    sending_[w][lane].clear();
  }
  take_arrived_lanes(ws, arrived);
  if (f < 0) return;
  std::vector<watch::AgentContext*> contexts;
  for (std::vector<watch::AgentContext>& thread : contexts_) contexts.push_back(&thread[w]);
  watch::AgentStepOutcome outcome = watch::sum_agent_step(contexts, f);
  add_up_over_ranks(ranks_, outcome);
  // The run's budget first: a context it held back proves the step passes it (watch::RunBudget);
  // one held back by its own budget wanted more than that, which is what it is charged.
  std::string over_run = whole_run ? run_budget_verdict(w, outcome.wanted) : std::string();
  watch::decide_agent_budget(outcome, f, hosted.options.live_budget);
  if (!over_run.empty() || outcome.over_budget) {
    // The step that went over a budget was cut short wherever each thread was: none of it is
    // reported.
    stop(ws, w, over_run.empty() ? std::move(outcome.stop_reason) : std::move(over_run));
    return;
  }
  out.observed = true;
  out.stats = std::move(outcome.stats);
  // Everything that matched now was started at t0 = f - (k - 1).
  const int64_t t0 = f - (k - 1);
  if (t0 < 0) return;
  out.t = t0;
  for (const watch::AgentContext* ctx : contexts) out.matches += ctx->match_values / k;
  out.matches = sum_over_ranks(ranks_, out.matches);
  if ((!lists_matches(hosted.action) && program.actions.empty()) || out.matches == 0) return;
  for (const watch::AgentContext* ctx : contexts) {
    out.slots.insert(out.slots.end(), ctx->matches.begin(),
                     ctx->matches.begin() + static_cast<ptrdiff_t>(ctx->match_values));
    out.actions.insert(out.actions.end(), ctx->action_values.begin(), ctx->action_values.end());
  }
  // Every rank's, on every rank: each decides alike where to pause, and acts alike.
  gather_over_ranks(ranks_, out.slots);
  if (!program.actions.empty()) gather_over_ranks(ranks_, out.actions);
}

// The PatternMatchers other ranks sent to this rank's blocks, appended to each block's first lane.
// Their order in the lanes matters to nothing (docs/design.md §4: a multiset), as with threads.
void WatchHosting::take_arrived_lanes(WatchState& ws, std::span<const ArrivedLane> arrived) const {
  if (ranks_ == nullptr) return;
  const uint32_t blocks = placement_.blocks();
  for (size_t lane = 0; lane < ws.in_flight.size(); ++lane)
    if (!ws.in_flight[lane].empty() && !placement_.owns_block(static_cast<uint32_t>(lane % blocks)))
      throw std::logic_error("a block taken for interior sent to another rank: its PatternMatchers would be lost");
  for (const ArrivedLane& lane : arrived)
    ws.in_flight[lane.block].append_records(lane.records.data(), lane.records.size());
}

void WatchHosting::observe_detector(uint32_t w, State& state, WatchStepOutput& out) {
  WatchState& ws = state.watches[w];
  const watch::Program& program = watches_[w].watchpoint.program;
  const bool keep = lists_matches(watches_[w].action) || !program.actions.empty();
  const uint32_t k = program.slot_count();
  ws.detector->set_sink(
      [&out, keep, k](int64_t t, std::span<const watch::ModuleId> ids, std::span<const watch::Value> actions) {
        out.t = t;
        out.matches += watch::match_rows(ids.size(), k);
        if (!keep) return;
        out.slots.assign(ids.begin(), ids.end());
        out.actions.assign(actions.begin(), actions.end());
      });
  if (passed_) {  // a watchpoint charged before it passed the run's budget at this step
    stop(ws, w, run_budget_verdict(w, 0));
    return;
  }
  // Over ranks only a zero-slot watchpoint has a detector (why_not_over_ranks): each rank observes
  // every module's values, gathered, and decides alike.
  const std::vector<int64_t> whole =
      ranks_ ? gather_values(*ranks_, placement_, model_.variable_count(), state.values) : std::vector<int64_t>{};
  const watch::Frame frame = make_frame(model_, state.step, ranks_ ? whole : state.values, state.present, state.graph);
  const uint64_t before = ws.detector->stats().observed_steps;
  ws.detector->observe(frame);
  if (ws.detector->stats().observed_steps > before) {  // a step cut short by the budget counts not
    out.observed = true;
    out.stats = ws.detector->stats().last;
  }
  // Stopped by its own budget, it wanted one more than it; else what its step held.
  const uint64_t own = watches_[w].options.live_budget;
  const uint64_t wanted = ws.detector->stopped() ? own + 1 : out.stats.live + out.stats.messages;
  if (std::string over_run = run_budget_verdict(w, wanted); !over_run.empty()) {
    out = WatchStepOutput{};  // the step that passed the budget reports nothing
    ws.stopped = true;
    ws.stop_reason = std::move(over_run);
  } else if (ws.detector->stopped()) {
    ws.stopped = true;
    ws.stop_reason = ws.detector->stats().stop_reason;
  }
}

// Matches in a fixed order whatever the thread count: by slot ids, their actions' values along.
void WatchHosting::sort_matches(uint32_t w, WatchStepOutput& o) const {
  if (o.slots.empty()) return;
  const uint32_t k = watches_[w].watchpoint.program.slot_count();
  std::vector<uint32_t> order(o.slots.size() / k);
  for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return std::lexicographical_compare(o.slots.begin() + a * k, o.slots.begin() + a * k + k, o.slots.begin() + b * k,
                                        o.slots.begin() + b * k + k);
  });
  std::vector<ModuleId> sorted;
  sorted.reserve(o.slots.size());
  for (uint32_t i : order) sorted.insert(sorted.end(), o.slots.begin() + i * k, o.slots.begin() + i * k + k);
  o.slots = std::move(sorted);
  if (const size_t a = watches_[w].watchpoint.program.actions.size(); a > 0) {
    std::vector<watch::Value> values;
    values.reserve(o.actions.size());
    for (uint32_t i : order) values.insert(values.end(), o.actions.begin() + i * a, o.actions.begin() + i * a + a);
    o.actions = std::move(values);
  }
}

// The actions of the matches decided this step, due at the start of the next (t + λ + 1): in
// watchpoint order, then match order (by slot ids; one step's matches share t), then action order.
void WatchHosting::queue_actions(State& state, std::span<const WatchStepOutput> out) const {
  for (uint32_t w = 0; w < size(); ++w) {
    const watch::Program& p = watches_[w].watchpoint.program;
    const WatchStepOutput& o = out[w];
    if (p.actions.empty() || o.slots.empty()) continue;
    const size_t k = static_cast<size_t>(p.slot_count()), a = p.actions.size();
    for (size_t i = 0; i * k < o.slots.size(); ++i)
      for (size_t j = 0; j < a; ++j) {
        const watch::ActionCode& code = p.actions[j];
        const watch::Value value = o.actions[i * a + j];
        PendingAction act;
        act.watch = w;
        act.module = o.slots[i * k + static_cast<size_t>(code.slot)];
        act.remove = code.kind == watch::Action::Kind::Remove;
        act.column = act.remove ? -1 : model_.column(code.variable);
        act.known = value.known;
        act.value = value.value;
        state.actions.push_back(act);
      }
  }
}

// An action whose value is unknown, whose module is absent by now or lacks the variable does
// nothing, and counts as skipped (docs/design.md §4b). A variable is set by its module's rank alone:
// no other holds it.
void WatchHosting::act(State& state, World& world) const {
  const uint32_t v = model_.variable_count();
  for (const PendingAction& a : state.actions) {
    WatchState& ws = state.watches[a.watch];
    const bool can =
        a.module < model_.module_count() && state.present[a.module] && (a.remove || (a.known && a.column >= 0));
    if (!can) {
      ++ws.actions_skipped;
      continue;
    }
    ++ws.actions_done;
    if (a.remove) world.remove_module(model_, state, a.module);
    else if (placement_.holds(a.module))
      state.values[size_t{a.module - placement_.first_module()} * v + size_t(a.column)] = a.value;
  }
  state.actions.clear();
}

// Over ranks, the agents of a watchpoint with an aggregate read their neighbours' values, which
// may be another rank's modules': every rank's values of the step are gathered and written into
// those agents' history, where the hop (watch::Program::agent_delay) reads them from the next step
// on. A whole gather, not only the border's: simple, and right whatever moves (and what `all` and
// `component()` read). Those that read the step's snapshot get them before they decide it.
void WatchHosting::share_neighbor_values(State& state) { share_values(state, state.values, false); }
void WatchHosting::share_step_values(State& state, std::span<const int64_t> values) {
  share_values(state, values, true);
}

void WatchHosting::share_values(State& state, std::span<const int64_t> values, bool late) {
  if (ranks_ == nullptr) return;
  std::vector<uint32_t> acting;
  for (uint32_t w : agent_watches_)
    if (!watches_[w].watchpoint.program.aggregates.empty() && state.watches[w].agents && snapshot_[w] == late)
      acting.push_back(w);
  if (!any_rank(ranks_, !acting.empty())) return;
  Gathered parts;
  const uint32_t v = model_.variable_count();
  const std::vector<std::span<const int64_t>> rows = gather_block_values(*ranks_, placement_, v, values, parts);
  for (uint32_t w : acting) {
    watch::AgentHistory& history = state.watches[w].agents->history();
    for (uint32_t b = 0; b < placement_.blocks(); ++b) {
      if (placement_.owns_block(b)) continue;
      const uint32_t begin = placement_.block_begin(b);
      for (uint32_t m = begin; m < placement_.block_begin(b + 1); ++m)
        for (size_t c = 0; c < columns_[w].size(); ++c) {
          if (columns_[w][c] < 0) continue;
          const int64_t value = rows[b][size_t{m - begin} * v + static_cast<size_t>(columns_[w][c])];
          history.set_value(m, static_cast<int>(c), state.step, value, state.present[m] != 0);
        }
    }
  }
}

}  // namespace dw::sim
