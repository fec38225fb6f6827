// The step loop (docs/design.md §2): `step` runs one step of the whole ensemble, shaped
// step(const Model&, State&) with the world and the worker threads beside it.
//
// Modules are split into blocks of consecutive ids (BlockPlacement), and each thread takes a run of
// consecutive blocks. Block by block, a thread runs the programs of the block's modules and then
// their distributed watchpoint agents (WatchHosting), so that an agent is brought into cache once
// per step. PatternMatchers go into a lane per (sending thread, receiving block): no two threads
// ever touch the same agent. Program messages are gathered in thread order, which is module order
// (MailboxSort), so every result is independent of the thread count. Over ranks, what crosses
// between them goes through RankStepping.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "sim/block_placement.h"
#include "sim/intervention.h"
#include "sim/mailbox.h"
#include "sim/model.h"
#include "sim/rank_exchange.h"
#include "sim/rank_stepping.h"
#include "sim/state.h"
#include "sim/watch_hosting.h"
#include "sim/worker_pool.h"
#include "sim/world.h"

namespace dw::sim {

struct StepOutput {
  int64_t step = -1;  // the step that ran
  // What the watchpoints saw of that step besides the variables (which the state still holds):
  // presence and N(m, step). The world has moved on to the next step's by the time step() returns.
  std::vector<uint8_t> present;
  std::shared_ptr<const NeighborGraph> graph;
  std::vector<WatchStepOutput> watches;
  uint64_t program_messages = 0;
};

// The frame of the step that `out` reports, while `state` still holds that step's variables.
inline watch::Frame observed_frame(const Model& model, const State& state, const StepOutput& out) {
  return make_frame(model, out.step, state.values, out.present, out.graph);
}

class Runtime {
 public:
  // `model` and `world` must outlive the runtime, and `ranks` too when given: then this process is
  // one rank of a run over several (docs/design.md §12). It steps the modules of the blocks `partition`
  // gives its rank; every rank keeps the world (its bodies and N(m, t)) whole, with the actuations
  // of all, and the rest of the state for its own modules only. The world may share its own work
  // among the ranks (World::share_over).
  // `watches` are the watchpoints it hosts beside the model (docs/design.md §2: a session's own),
  // where their owner keeps them: they must outlive the runtime, which is made again when they change.
  Runtime(const Model& model, HostedWatches watches, World& world, unsigned threads, RankExchange* ranks = nullptr,
          Partition partition = Partition::Auto);

  // The state before step 0: initial values, the world's step-0 topology, fresh detectors.
  State initial_state();
  // A fresh detector state for watchpoint w, as before step 0.
  WatchState initial_watch_state(uint32_t w) const;
  // Runs step state.step and leaves the state ready for the next one. `interventions` are those
  // of this step, carried out first in their order (a bad one throws ProgramError), after the
  // watchpoints' actions due then (docs/design.md §4b). Only the watchpoints `watching` marks (all when
  // empty) observe the step, and those with actions, which are part of the simulation; the
  // others' states are left as they were, so a session can re-simulate for one watchpoint, or
  // for none.
  void step(State& state, StepOutput& out, std::span<const Intervention> interventions = {},
            std::span<const uint8_t> watching = {});

  // The run is over: the agents of watchpoint w, which wait a hop for their neighbours' values
  // (an aggregate's, watch::Program::agent_delay), decide the detector steps the last frames
  // allow from the history they hold, one call per detector step f (docs/design.md §7). Over ranks, a
  // collective call.
  void drain_agents(State& state, uint32_t w, int64_t f, WatchStepOutput& out);

  // Runs `program` as program p from the next step on (a script reloaded, Session::replace_programs;
  // it keeps p's variables), each thread with a fresh scratch for it.
  void use_program(uint32_t p, const HostProgram& program);

  // The whole run's PatternMatcher budget over the next step, and what the last step charged
  // (WatchHosting::charge_before, charged).
  void charge_before(std::optional<uint64_t> others) { hosting_.charge_before(others); }
  uint64_t charged() const { return hosting_.charged(); }

  const Model& model() const { return model_; }
  World& world() { return world_; }
  unsigned threads() const { return pool_.size(); }

  // The modules whose variables, inboxes and agents this process's states hold: [first, first +
  // count), all of them in one process; over ranks, from its first block to its last (docs/design.md §12).
  uint32_t first_module() const { return placement_.first_module(); }
  uint32_t module_window() const { return placement_.module_window(); }

  // The state hash (hash_state) of the whole ensemble: over several ranks, of the parts every rank
  // holds, on every rank (a collective call).
  StateHash hash(const State& state);
  // The variables of every module in `state` (model order): over several ranks, gathered from the
  // rank of each (a collective call); otherwise state.values.
  std::vector<int64_t> whole_values(const State& state);
  // N(m, t) of every module: over several ranks, when `graph` is a rank's window of it, gathered
  // from the rank of each (a collective call); otherwise `graph`.
  std::shared_ptr<const NeighborGraph> whole_graph(const std::shared_ptr<const NeighborGraph>& graph);
  // Bytes this rank has sent to the others since the runtime was made: program messages and
  // PatternMatchers (the per-step batches), not the gathers of matches and statistics.
  uint64_t bytes_to_ranks() const { return over_ranks_ ? over_ranks_->bytes_sent() : 0; }
  // Wall-clock seconds the world took moving on (World::advance: physics, contacts, the graph),
  // over every step this runtime ran.
  double world_seconds() const { return world_seconds_; }
  // How the modules are shared among the ranks: Blocks or Graph (Auto decided).
  Partition partition() const { return placement_.partition(); }

 private:
  struct ThreadScratch {
    Outbox outbox;
    std::vector<std::unique_ptr<ProgramScratch>> programs;  // per program (HostProgram::make_scratch)
  };

  void intervene(State& state, std::span<const Intervention> interventions);
  void start_thread(unsigned thread, const State& state);
  void run_blocks(unsigned thread, std::span<const uint32_t> blocks, State& state);
  void run_late_agents(State& state);
  void run_over_ranks(State& state);
  void run_programs(unsigned thread, uint32_t begin, uint32_t end, const State& state);
  // fn(0) .. fn(threads - 1): on the pool, or one after another on the caller's thread when a
  // program runs in module order (HostProgram::in_module_order).
  void run_threads(const std::function<void(unsigned)>& fn);
  void note_module_order();
  void agree_on_failure_and_gather_actuations(int64_t step);
  void deliver_program_messages(State& state);
  std::vector<Messages> sent_messages() const;                      // per thread, this step's
  std::span<const std::vector<ArrivedLane>> arrived_lanes() const;  // from the other ranks, per watch

  const Model& model_;
  World& world_;
  WorkerPool pool_;
  RankExchange* ranks_;  // null: this process runs every module
  BlockPlacement placement_;
  WatchHosting hosting_;
  std::optional<RankStepping> over_ranks_;  // over ranks only
  MailboxSort mailbox_;
  double world_seconds_ = 0;
  std::vector<ThreadScratch> scratch_;
  std::vector<const HostProgram*> programs_;  // in use, by index: the model's unless replaced
  bool in_module_order_ = false;              // one of them runs in module order
  std::vector<int64_t> next_values_;
  std::vector<Actuation> actuations_;  // the step's, for the world
};

}  // namespace dw::sim
