#include "sim/runtime.h"

#include <algorithm>
#include <cstring>

#include "watch/agent_step.h"
#include "watch/make_detector.h"

namespace dw::sim {

// A thread's PatternMatcher outbox: each copy goes into the lane of its receiver's block.
struct Runtime::Lanes final : watch::PatternMatcherOutbox {
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
                        std::span<const uint8_t> present, const std::shared_ptr<const NeighborGraph>& graph) {
  watch::Frame frame;
  frame.step = step;
  frame.present = present;
  frame.values = values;
  frame.has_value = model.all_known;
  frame.nbr_begin = graph->begin;
  frame.nbrs = graph->ids;
  frame.variable_count = model.variable_count();
  frame.topology = graph;
  return frame;
}

Runtime::Runtime(const Model& model, World& world, unsigned threads)
    : model_(model), world_(world), pool_(std::max(1u, std::min(threads, std::max(1u, model.module_count())))) {
  // Blocks of at most 4096 modules (a power of two). A neighbour list that crosses a block boundary
  // is sent as one record per block, so blocks are as large as the threads allow: one thread takes
  // the ensemble as one block (up to 4096), and several take at least one block each, never so
  // large that a thread is left without one.
  const uint32_t m = model.module_count();
  const uint32_t per_thread = std::max(1u, m / pool_.size());
  if (pool_.size() == 1)
    while (block_shift_ < 12 && (1u << block_shift_) < per_thread) ++block_shift_;
  else
    while (block_shift_ < 12 && (2u << block_shift_) <= per_thread) ++block_shift_;
  blocks_ = (m >> block_shift_) + ((m & ((1u << block_shift_) - 1)) != 0);
  scratch_.resize(pool_.size());
  arriving_.resize(pool_.size());
  for (const auto& program : model.programs) programs_.push_back(program.get());
  for (ThreadScratch& s : scratch_) {
    for (const auto& program : model.programs) s.programs.push_back(program->make_scratch());
    for (const HostedWatchpoint& w : model.watches) {
      // Each thread may use the whole budget; whether the step went over it is decided on the
      // threads' sum afterwards (finish_distributed), so the stop never depends on the thread count.
      s.agents.emplace_back(w.watchpoint.program, w.options.optimizations, w.options.live_budget);
    }
  }
  next_values_.resize(size_t{m} * model.variable_count());
  const size_t lanes = size_t{pool_.size()} * blocks_;
  for (const HostedWatchpoint& w : model.watches) {
    columns_.push_back(watch::variable_columns(w.watchpoint.program, model.universe));
    sending_.emplace_back(w.runs_on_agents() ? lanes : 0);
  }
}

void Runtime::use_program(uint32_t p, const HostProgram& program) {
  if (programs_[p] == &program) return;
  programs_[p] = &program;
  for (ThreadScratch& s : scratch_) s.programs[p] = program.make_scratch();
}

uint32_t Runtime::first_block(unsigned thread) const {
  return static_cast<uint32_t>(uint64_t{thread} * blocks_ / pool_.size());
}

uint32_t Runtime::block_begin(uint32_t block) const {
  return static_cast<uint32_t>(std::min<uint64_t>(uint64_t{block} << block_shift_, model_.module_count()));
}

State Runtime::initial_state() {
  State s;
  const uint32_t m = model_.module_count(), v = model_.variable_count();
  s.values.resize(size_t{m} * v);
  for (uint32_t i = 0; i < m; ++i)
    std::copy(model_.initial_values.begin(), model_.initial_values.end(), s.values.begin() + size_t{i} * v);
  world_.initialize(model_, s);
  for (uint32_t w = 0; w < model_.watches.size(); ++w) s.watches.push_back(initial_watch_state(w));
  return s;
}

WatchState Runtime::initial_watch_state(uint32_t w) const {
  const HostedWatchpoint& h = model_.watches[w];
  WatchState ws;
  if (!h.runs_on_agents()) {
    ws.detector = watch::make_detector(h.algorithm, h.watchpoint, model_.universe, h.options, nullptr);
    ws.detector->stats().max_steps = 0;  // the run keeps its own series
  } else {
    ws.agents.emplace(h.watchpoint.program, h.options.optimizations.temporal_spans, model_.module_count());
    ws.in_flight.resize(size_t{pool_.size()} * blocks_);
  }
  return ws;
}

void Runtime::run_programs(unsigned thread, uint32_t begin, uint32_t end, const State& state) {
  const uint32_t v = model_.variable_count(), programs = model_.program_count();
  ThreadScratch& scratch = scratch_[thread];
  for (uint32_t m = begin; m < end; ++m) {
    const int64_t* before = state.values.data() + size_t{m} * v;
    int64_t* after = next_values_.data() + size_t{m} * v;
    std::memcpy(after, before, sizeof(int64_t) * v);  // a variable nobody assigns keeps its value
    if (!state.present[m]) continue;
    const auto neighbors = state.graph->neighbors(m);
    for (uint32_t p = 0; p < programs; ++p) {
      const uint32_t base = model_.program_base[p];
      const HostProgram& program = *programs_[p];
      ModuleContext ctx(m, state.step, model_.seed, static_cast<uint16_t>(p), neighbors, state.inbox.of(m, p, programs),
                        before + base, after + base, scratch.outbox, program.name(), state.bodies,
                        scratch.programs[p].get());
      program.step(ctx);
    }
  }
}

// One block of agents for one watchpoint, in the order that keeps the block's agents in cache:
// each records its module's state at t and decides its own leaves, then the PatternMatchers sent
// to the block arrive, then every agent starts its own (watch/agent_step.h).
void Runtime::run_agents(unsigned thread, uint32_t block, uint32_t w, State& state) {
  const watch::Program& program = model_.watches[w].watchpoint.program;
  WatchState& ws = state.watches[w];
  const uint32_t begin = block_begin(block), end = block_begin(block + 1);
  const watch::Frame frame = make_frame(model_, state.step, next_values_, state.present, state.graph);
  ws.agents->record(frame, begin, end, program, columns_[w]);
  const int64_t f = state.step - program.extent_plus;
  if (f < 0) return;
  Lanes out;
  out.row = sending_[w].data() + size_t{thread} * blocks_;
  out.block_shift = block_shift_;
  arriving_[thread].clear();
  for (unsigned from = 0; from < pool_.size(); ++from)
    arriving_[thread].push_back(&ws.in_flight[size_t{from} * blocks_ + block]);
  watch::step_agents(*ws.agents, begin, end, f, arriving_[thread], scratch_[thread].agents[w], out);
}

void Runtime::run_thread(unsigned thread, State& state) {
  ThreadScratch& s = scratch_[thread];
  s.outbox.messages.clear();
  s.outbox.actuations.clear();
  s.outbox.error.clear();  // a failed step may be tried again (a script reloaded, a seek back)
  for (uint32_t w : agent_watches_)
    watch::start_agent_step(s.agents[w], state.step - model_.watches[w].watchpoint.program.extent_plus);
  for (uint32_t block = first_block(thread); block < first_block(thread + 1); ++block) {
    run_programs(thread, block_begin(block), block_begin(block + 1), state);
    for (uint32_t w : agent_watches_) run_agents(thread, block, w, state);
  }
}

// Gathers the threads' matches and statistics; the PatternMatchers sent become those in flight.
void Runtime::finish_distributed(uint32_t w, State& state, WatchStepOutput& out) {
  const HostedWatchpoint& hosted = model_.watches[w];
  const watch::Program& program = hosted.watchpoint.program;
  WatchState& ws = state.watches[w];
  const uint32_t k = program.slot_count();
  const int64_t f = state.step - program.extent_plus;
  for (size_t lane = 0; lane < ws.in_flight.size(); ++lane) {
    std::swap(ws.in_flight[lane], sending_[w][lane]);
    sending_[w][lane].clear();
  }
  if (f < 0) return;
  std::vector<watch::AgentContext*> contexts;
  for (ThreadScratch& s : scratch_) contexts.push_back(&s.agents[w]);
  watch::AgentStepOutcome outcome = watch::finish_agent_step(contexts, f, hosted.options.live_budget);
  if (outcome.over_budget) {
    // The step that went over the budget was cut short wherever each thread was: none of it is
    // reported, and the stopped watch lets go of its agents and PatternMatchers.
    ws.stopped = true;
    ws.stop_reason = std::move(outcome.stop_reason);
    ws.agents.reset();
    ws.in_flight = {};
    for (watch::RecordBuffer& lane : sending_[w]) lane = {};
    return;
  }
  out.observed = true;
  out.stats = std::move(outcome.stats);
  // Everything that matched now was started at t0 = f - (k - 1).
  const int64_t t0 = state.step - hosted.lag();
  if (t0 >= 0) {
    out.t = t0;
    for (ThreadScratch& s : scratch_) out.matches += s.agents[w].match_values / k;
    if (hosted.action != MatchAction::Count && out.matches) {
      for (ThreadScratch& s : scratch_)
        out.slots.insert(out.slots.end(), s.agents[w].matches.begin(),
                         s.agents[w].matches.begin() + static_cast<ptrdiff_t>(s.agents[w].match_values));
    }
  }
}

void Runtime::observe_detector(uint32_t w, State& state, WatchStepOutput& out) {
  WatchState& ws = state.watches[w];
  const bool keep = model_.watches[w].action != MatchAction::Count;
  const uint32_t k = model_.watches[w].watchpoint.program.slot_count();
  ws.detector->set_sink([&out, keep, k](int64_t t, std::span<const watch::ModuleId> ids) {
    out.t = t;
    out.matches += ids.size() / k;
    if (keep) out.slots.assign(ids.begin(), ids.end());
  });
  const watch::Frame frame = make_frame(model_, state.step, state.values, state.present, state.graph);
  const uint64_t before = ws.detector->stats().observed_steps;
  ws.detector->observe(frame);
  if (ws.detector->stats().observed_steps > before) {  // a step cut short by the budget counts not
    out.observed = true;
    out.stats = ws.detector->stats().last;
  }
  if (ws.detector->stopped()) {
    ws.stopped = true;
    ws.stop_reason = ws.detector->stats().stop_reason;
  }
}

void Runtime::deliver_program_messages(State& state) {
  const uint32_t programs = model_.program_count();
  const size_t groups = size_t{model_.module_count()} * programs;
  size_t total = 0;
  for (const ThreadScratch& s : scratch_) total += s.outbox.messages.size();
  Mailbox& box = state.inbox;
  box.begin.assign(groups + 1, 0);
  box.messages.resize(total);
  if (total == 0) return;
  // A stable counting sort by (receiver, program): senders stay in id order within a group.
  for (const ThreadScratch& s : scratch_)
    for (const Message& m : s.outbox.messages) ++box.begin[size_t{m.to} * programs + m.program + 1];
  for (size_t g = 0; g < groups; ++g) box.begin[g + 1] += box.begin[g];
  counts_.assign(box.begin.begin(), box.begin.end() - 1);
  for (const ThreadScratch& s : scratch_)
    for (const Message& m : s.outbox.messages) box.messages[counts_[size_t{m.to} * programs + m.program]++] = m;
  state.program_messages += total;
}

void Runtime::intervene(State& state, std::span<const Intervention> interventions) {
  const uint32_t v = model_.variable_count();
  for (const Intervention& i : interventions) {
    if (i.module >= model_.module_count() ||
        (i.kind == Intervention::Kind::Set && (i.column < 0 || uint32_t(i.column) >= v)))
      throw ProgramError(std::string("a ") + intervention_name(i.kind) + " intervention at step " +
                         std::to_string(i.at) + " names no module or variable of the model");
    switch (i.kind) {
      case Intervention::Kind::Set: state.values[size_t{i.module} * v + size_t(i.column)] = i.value; break;
      case Intervention::Kind::Remove: world_.remove_module(model_, state, i.module); break;
      case Intervention::Kind::Push:
        if (state.bodies.empty())
          throw ProgramError("a push on module " + std::to_string(i.module) + " at step " + std::to_string(i.at) +
                             " needs bodies: the scenario has no physics");
        actuations_.push_back({Actuation::Kind::Push, i.module, 0, i.impulse});
        break;
    }
  }
}

void Runtime::step(State& state, StepOutput& out, std::span<const Intervention> interventions,
                   std::span<const uint8_t> watching) {
  out.step = state.step;
  out.watches.assign(model_.watches.size(), WatchStepOutput{});
  // Pushes made from outside go to the world first, then the programs' own requests.
  actuations_.clear();
  intervene(state, interventions);
  // The watchpoints whose agents run this step make room for it before the threads record it.
  agent_watches_.clear();
  for (uint32_t w = 0; w < model_.watches.size(); ++w) {
    if (!model_.watches[w].runs_on_agents() || state.watches[w].stopped) continue;
    if (!watching.empty() && !watching[w]) continue;
    agent_watches_.push_back(w);
    state.watches[w].agents->begin_record(make_frame(model_, state.step, next_values_, state.present, state.graph));
  }
  pool_.run([&](unsigned thread) { run_thread(thread, state); });
  for (const ThreadScratch& s : scratch_)
    if (!s.outbox.error.empty()) throw ProgramError(s.outbox.error, s.outbox.error_module, s.outbox.error_step);

  std::swap(state.values, next_values_);  // assign: the variables now hold step t's values
  for (uint32_t w = 0; w < model_.watches.size(); ++w) {
    if (state.watches[w].stopped || (!watching.empty() && !watching[w])) continue;
    if (model_.watches[w].runs_on_agents()) finish_distributed(w, state, out.watches[w]);
    else observe_detector(w, state, out.watches[w]);
    WatchStepOutput& o = out.watches[w];
    state.watches[w].matches += o.matches;
    // Matches in a fixed order whatever the thread count: by slot ids.
    if (!o.slots.empty()) {
      const uint32_t k = model_.watches[w].watchpoint.program.slot_count();
      std::vector<uint32_t> order(o.slots.size() / k);
      for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
      std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
        return std::lexicographical_compare(o.slots.begin() + a * k, o.slots.begin() + a * k + k,
                                            o.slots.begin() + b * k, o.slots.begin() + b * k + k);
      });
      std::vector<ModuleId> sorted;
      sorted.reserve(o.slots.size());
      for (uint32_t i : order) sorted.insert(sorted.end(), o.slots.begin() + i * k, o.slots.begin() + i * k + k);
      o.slots = std::move(sorted);
    }
  }
  out.present = state.present;
  out.graph = state.graph;
  const uint64_t sent_before = state.program_messages;
  deliver_program_messages(state);
  out.program_messages = state.program_messages - sent_before;
  // Actuation requests in thread order, which is module order.
  for (const ThreadScratch& s : scratch_)
    actuations_.insert(actuations_.end(), s.outbox.actuations.begin(), s.outbox.actuations.end());
  ++state.step;
  world_.advance(model_, state, actuations_);
}

}  // namespace dw::sim
