#include "sim/runtime.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "sim/read_file.h"
#include "sim/whole_over_ranks.h"

namespace dw::sim {

Runtime::Runtime(const Model& model, HostedWatches watches, World& world, unsigned threads, RankExchange* ranks,
                 Partition partition)
    : model_(model),
      world_(world),
      pool_(std::max(1u, std::min(threads, std::max(1u, model.module_count())))),
      ranks_(ranks),
      placement_(model, pool_.size(), ranks, partition, world.moves()),
      hosting_(model, std::move(watches), placement_, pool_.size(), ranks) {
  if (ranks_) over_ranks_.emplace(*ranks_, placement_, pool_.size());
  world_.share_over(ranks_, placement_.owners());
  scratch_.resize(pool_.size());
  for (const auto& program : model.programs) programs_.push_back(program.get());
  for (ThreadScratch& s : scratch_) {
    s.outbox.byte_limit = model.message_bytes_per_step;
    for (const auto& program : model.programs) s.programs.push_back(program->make_scratch());
  }
  note_module_order();
  next_values_.resize(size_t{placement_.module_window()} * model.variable_count());
}

void Runtime::use_program(uint32_t p, const HostProgram& program) {
  if (programs_[p] == &program) return;
  programs_[p] = &program;
  for (ThreadScratch& s : scratch_) s.programs[p] = program.make_scratch();
  note_module_order();
}

void Runtime::note_module_order() {
  in_module_order_ =
      std::any_of(programs_.begin(), programs_.end(), [](const HostProgram* p) { return p->in_module_order(); });
}

// Each thread's share keeps its own scratch, outbox and lanes either way: run in turn, the shares
// give what they give in parallel, and their programs' calls come in module order.
void Runtime::run_threads(const std::function<void(unsigned)>& fn) {
  if (!in_module_order_) return pool_.run(fn);
  for (unsigned thread = 0; thread < pool_.size(); ++thread) fn(thread);
}

State Runtime::initial_state() {
  State s;
  const uint32_t v = model_.variable_count(), window = placement_.module_window();
  s.values.resize(size_t{window} * v);
  for (uint32_t i = 0; i < window; ++i)
    std::copy(model_.initial_values.begin(), model_.initial_values.end(), s.values.begin() + size_t{i} * v);
  world_.initialize(model_, s, pool_);
  for (uint32_t w = 0; w < hosting_.size(); ++w) s.watches.push_back(initial_watch_state(w));
  return s;
}

WatchState Runtime::initial_watch_state(uint32_t w) const { return hosting_.initial_state(w); }

void Runtime::run_programs(unsigned thread, uint32_t begin, uint32_t end, const State& state) {
  const uint32_t v = model_.variable_count(), programs = model_.program_count(), first = placement_.first_module();
  ThreadScratch& scratch = scratch_[thread];
  for (uint32_t m = begin; m < end; ++m) {
    const int64_t* before = state.values.data() + size_t{m - first} * v;
    int64_t* after = next_values_.data() + size_t{m - first} * v;
    // A variable nobody assigns keeps its value. (A model without variables has no rows: their
    // pointers may be null, which memcpy may not be given even for no bytes.)
    if (v > 0) std::memcpy(after, before, sizeof(int64_t) * v);
    if (!state.present[m]) continue;
    const auto neighbors = state.graph->neighbors(m);
    for (uint32_t p = 0; p < programs; ++p) {
      // Once a module has failed, the step fails with the lowest failing module's message: the
      // calls of higher modules on this thread cannot change it and are not made (a script looping
      // to its budget on every module took minutes to report module 0's failure).
      if (!scratch.outbox.error.empty() && scratch.outbox.error_module <= m) break;
      const uint32_t base = model_.program_base[p];
      const HostProgram& program = *programs_[p];
      ModuleContext ctx(m, state.step, model_.seed, static_cast<uint16_t>(p), neighbors,
                        state.inbox.of(m - first, p, programs), before + base, after + base, scratch.outbox,
                        program.name(), state.bodies, scratch.programs[p].get());
      program.step(ctx);
    }
  }
}

void Runtime::start_thread(unsigned thread, const State& state) {
  ThreadScratch& s = scratch_[thread];
  s.outbox.messages.clear();
  s.outbox.actuations.clear();
  s.outbox.error.clear();  // a failed step may be tried again (a script reloaded, a seek back)
  s.outbox.over = false;
  hosting_.start_thread(thread, state.step);
}

// The thread's share of `blocks`: the t-th of equal runs.
void Runtime::run_blocks(unsigned thread, std::span<const uint32_t> blocks, State& state) {
  const size_t n = blocks.size();
  for (size_t i = thread * n / pool_.size(); i < (thread + 1) * n / pool_.size(); ++i) {
    if (over_ranks_) over_ranks_->progress(thread);
    run_programs(thread, placement_.block_begin(blocks[i]), placement_.block_begin(blocks[i] + 1), state);
    hosting_.run_block(thread, blocks[i], state, next_values_);
  }
}

// The agents of watchpoints that read the step's snapshot (`all`, `component()`), once every block
// has recorded the step: the thread's share of the own blocks, as run_blocks shares them.
void Runtime::run_late_agents(State& state) {
  const std::span<const uint32_t> blocks = placement_.own_blocks();
  pool_.run([&](unsigned thread) {
    const size_t n = blocks.size();
    for (size_t i = thread * n / pool_.size(); i < (thread + 1) * n / pool_.size(); ++i)
      hosting_.run_late_block(thread, blocks[i], state);
  });
}

// Over ranks, the blocks that may send to another rank run first; their batches then travel while
// the interior blocks run, and what the other ranks sent is taken in at the end (docs/design.md §12).
void Runtime::run_over_ranks(State& state) {
  over_ranks_->split_blocks(state, hosting_);
  run_threads([&](unsigned thread) {
    start_thread(thread, state);
    run_blocks(thread, over_ranks_->border_blocks(), state);
    over_ranks_->set_border_messages(thread, scratch_[thread].outbox.messages.size());
  });
  // Agents that read the step's snapshot send only once every rank has run the step: then the
  // batches leave after them, the interior blocks not overlapping the exchange.
  const bool late = hosting_.late_agents();
  if (!late) over_ranks_->start_exchange(sent_messages(), hosting_);
  run_threads([&](unsigned thread) { run_blocks(thread, over_ranks_->interior_blocks(), state); });
  if (late) {
    hosting_.share_step_values(state, next_values_);
    run_late_agents(state);
    over_ranks_->start_exchange(sent_messages(), hosting_);
  }
  over_ranks_->finish_exchange(hosting_);
}

std::span<const std::vector<ArrivedLane>> Runtime::arrived_lanes() const {
  return over_ranks_ ? over_ranks_->arrived_lanes() : std::span<const std::vector<ArrivedLane>>{};
}

std::vector<Messages> Runtime::sent_messages() const {
  std::vector<Messages> sent;
  for (const ThreadScratch& s : scratch_) sent.push_back(s.outbox.messages.all());
  return sent;
}

void Runtime::drain_agents(State& state, uint32_t w, int64_t f, WatchStepOutput& out) {
  if (state.watches[w].stopped) return;
  out = WatchStepOutput{};
  hosting_.drain_begin(w);
  for (ThreadScratch& s : scratch_) s.outbox.messages.clear();
  pool_.run([&](unsigned thread) { hosting_.drain_blocks(thread, w, f, state); });
  if (over_ranks_) {
    over_ranks_->start_exchange(sent_messages(), hosting_);
    over_ranks_->finish_exchange(hosting_);
  }
  hosting_.drain_finish(state, w, f, out, arrived_lanes());
}

void Runtime::deliver_program_messages(State& state) {
  const std::vector<Messages> sent = sent_messages();
  if (over_ranks_) over_ranks_->check_interior_messages(sent);
  const uint64_t delivered = mailbox_.fill(state.inbox, placement_, model_.program_count(), sent,
                                           over_ranks_ ? over_ranks_->arrived_messages() : std::span<const Messages>{});
  state.program_messages += sum_over_ranks(ranks_, delivered);  // every message is received by exactly one rank
}

std::vector<int64_t> Runtime::whole_values(const State& state) {
  if (!ranks_) return state.values;
  return gather_values(*ranks_, placement_, model_.variable_count(), state.values);
}

std::shared_ptr<const NeighborGraph> Runtime::whole_graph(const std::shared_ptr<const NeighborGraph>& graph) {
  if (!ranks_ || !graph->held) return graph;
  return gather_graph(*ranks_, placement_, *graph);
}

// Over ranks, the whole state as one process would hold it.
StateHash Runtime::hash(const State& state) {
  if (!ranks_) return hash_state(state);
  return hash_over_ranks(*ranks_, placement_, model_, state);
}

void Runtime::intervene(State& state, std::span<const Intervention> interventions) {
  const uint32_t v = model_.variable_count();
  for (const Intervention& i : interventions) {
    if (i.module >= model_.module_count() ||
        (i.kind == Intervention::Kind::Set && (i.column < 0 || uint32_t(i.column) >= v)))
      throw ProgramError(std::string("a ") + intervention_name(i.kind) + " intervention at step " +
                         std::to_string(i.at) + " names no module or variable of the model");
    switch (i.kind) {
      case Intervention::Kind::Set:  // the module's rank's alone: no other holds its variables
        if (placement_.holds(i.module))
          state.values[size_t{i.module - placement_.first_module()} * v + size_t(i.column)] = i.value;
        break;
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

// A program's misuse on any rank stops every rank, with the first one in module order, as one
// process reports it (each thread's outbox keeps its lowest module's). Otherwise the actuation
// requests go to the world in module order, as one process has them (in thread order): the world
// is stepped whole on every rank, so every rank needs all of them. One sum over the ranks says
// whether either has to be gathered. Without a misuse, messages past Model::message_bytes_per_step
// in a process stop every rank: a thread past it alone means the process's are, so whether the
// step stops does not depend on the threads.
void Runtime::agree_on_failure_and_gather_actuations(int64_t step) {
  const Outbox* failed = nullptr;
  const size_t before = actuations_.size();  // the interventions' pushes come first
  uint64_t message_bytes = 0;
  bool over = false;
  for (const ThreadScratch& s : scratch_) {
    if (!s.outbox.error.empty() && (!failed || s.outbox.error_module < failed->error_module)) failed = &s.outbox;
    actuations_.insert(actuations_.end(), s.outbox.actuations.begin(), s.outbox.actuations.end());
    message_bytes += s.outbox.messages.used_bytes();
    over = over || s.outbox.over;
  }
  const uint64_t limit = model_.message_bytes_per_step;
  over = over || (limit > 0 && message_bytes > limit);
  uint64_t counts[3] = {failed != nullptr, actuations_.size() - before, over};
  sum_over_ranks(ranks_, counts);
  if (over_ranks_ && counts[0] != 0) throw over_ranks_->agreed_failure(failed);
  if (failed) throw ProgramError(failed->error, failed->error_module, failed->error_step);
  if (counts[2] != 0)
    throw ProgramError("at step " + std::to_string(step) + " the modules' messages took more than " + size_text(limit) +
                       (ranks_ ? " in one process" : "") +
                       ", what a step's messages may take on this machine beyond the scenario's memory estimate (a "
                       "program sending without end?)");
  if (over_ranks_ && counts[1] != 0) over_ranks_->gather_actuations(actuations_, before);
}

void Runtime::step(State& state, StepOutput& out, std::span<const Intervention> interventions,
                   std::span<const uint8_t> watching) {
  out.step = state.step;
  out.watches.assign(hosting_.size(), WatchStepOutput{});
  // Pushes made from outside go to the world first, then the programs' own requests.
  actuations_.clear();
  hosting_.act(state, world_);
  intervene(state, interventions);
  // The watchpoints whose agents run this step make room for it before the threads record it.
  hosting_.begin_step(state, watching, next_values_);
  if (over_ranks_) {
    run_over_ranks(state);
  } else {
    run_threads([&](unsigned thread) {
      start_thread(thread, state);
      run_blocks(thread, placement_.own_blocks(), state);
    });
    if (hosting_.late_agents()) run_late_agents(state);
  }
  agree_on_failure_and_gather_actuations(state.step);

  std::swap(state.values, next_values_);  // assign: the variables now hold step t's values
  hosting_.finish_step(state, out.watches, watching, arrived_lanes());
  hosting_.queue_actions(state, out.watches);
  hosting_.share_neighbor_values(state);
  out.present = state.present;
  out.graph = state.graph;
  const uint64_t sent_before = state.program_messages;
  deliver_program_messages(state);
  out.program_messages = state.program_messages - sent_before;
  ++state.step;
  const auto moving_on = std::chrono::steady_clock::now();
  world_.advance(model_, state, actuations_, pool_);
  world_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - moving_on).count();
  // The run hash chains the simulation as it stands after the step, the same on every thread and
  // rank count; a state restored from the history carries its own (a seek's steps chain it again).
  const uint64_t simulation =
      ranks_ ? simulation_hash_over_ranks(*ranks_, placement_, model_, state) : simulation_hash(state);
  state.run_hash = next_run_hash(state.run_hash, simulation);
}

}  // namespace dw::sim
