// The step loop (docs/design.md §2): `step` runs one step of the whole ensemble, shaped
// step(const Model&, State&) with the world and the worker threads beside it.
//
// Modules are split into blocks of consecutive ids (at most 4096), and each thread takes a run of
// consecutive blocks. Block by block, a thread runs the programs of the block's modules and then
// their distributed watchpoint agents, so that an agent is brought into cache once per step.
// PatternMatchers go into a lane per (sending thread, receiving block): no two threads ever touch
// the same agent. Program messages are gathered in thread order, which is module order, so every
// result is independent of the thread count.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "sim/intervention.h"
#include "sim/model.h"
#include "sim/rank_exchange.h"
#include "sim/state.h"
#include "sim/worker_pool.h"
#include "sim/world.h"

namespace dw::watch {
struct AgentStepOutcome;  // watch/agent_step.h
}

namespace dw::sim {

// What one hosted watchpoint decided during a step.
struct WatchStepOutput {
  int64_t t = -1;  // the watch step whose matches were decided now; -1 when none was
  uint64_t matches = 0;
  std::vector<ModuleId> slots;        // slot ids per match, matches in ascending order; not for `count`
                                      // unless it has actions
  std::vector<watch::Value> actions;  // per match, its actions' values (docs/design.md §4b)
  bool observed = false;              // stats holds this step's statistics
  watch::StepStats stats;
};

struct StepOutput {
  int64_t step = -1;  // the step that ran
  // What the watchpoints saw of that step besides the variables (which the state still holds):
  // presence and N(m, step). The world has moved on to the next step's by the time step() returns.
  std::vector<uint8_t> present;
  std::shared_ptr<const NeighborGraph> graph;
  std::vector<WatchStepOutput> watches;
  uint64_t program_messages = 0;
};

// The frame the watchpoints see of a step: the variables (of the modules from `first_module` on;
// all of them but over ranks), presence and N(m, step) (lent, see Frame::topology).
watch::Frame make_frame(const Model& model, int64_t step, std::span<const int64_t> values,
                        std::span<const uint8_t> present, const std::shared_ptr<const NeighborGraph>& graph,
                        uint32_t first_module = 0);
// The frame of the step that `out` reports, while `state` still holds that step's variables.
inline watch::Frame observed_frame(const Model& model, const State& state, const StepOutput& out) {
  return make_frame(model, out.step, state.values, out.present, out.graph);
}

// Why `model` cannot run over several ranks, or empty when it can (docs/design.md §12): a centralized or
// simultaneous-state detector observes the whole ensemble in one place, which no rank holds.
std::string why_not_over_ranks(const Model& model);

class Runtime {
 public:
  // `model` and `world` must outlive the runtime, and `ranks` too when given: then this process is
  // one rank of a run over several (docs/design.md §12). It steps the modules of the blocks `partition`
  // gives its rank; every rank keeps the world (its bodies and N(m, t)) whole, with the actuations
  // of all, and the rest of the state for its own modules only. The world may share its own work
  // among the ranks (World::share_over).
  Runtime(const Model& model, World& world, unsigned threads, RankExchange* ranks = nullptr,
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

  const Model& model() const { return model_; }
  World& world() { return world_; }
  unsigned threads() const { return pool_.size(); }

  // The modules whose variables, inboxes and agents this process's states hold: [first, first +
  // count), all of them in one process; over ranks, from its first block to its last (docs/design.md §12).
  uint32_t first_module() const { return first_; }
  uint32_t module_window() const { return window_; }

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
  uint64_t bytes_to_ranks() const { return bytes_to_ranks_; }
  // Wall-clock seconds the world took moving on (World::advance: physics, contacts, the graph),
  // over every step this runtime ran.
  double world_seconds() const { return world_seconds_; }
  // How the modules are shared among the ranks: Blocks or Graph (Auto decided).
  Partition partition() const { return partition_; }

 private:
  struct Lanes;  // a thread's PatternMatcher outbox
  struct ThreadScratch {
    Outbox outbox;
    std::vector<std::unique_ptr<ProgramScratch>> programs;  // per program (HostProgram::make_scratch)
    std::vector<watch::AgentContext> agents;                // per watchpoint (distributed ones used)
  };

  void intervene(State& state, std::span<const Intervention> interventions);
  void act(State& state);
  bool observes(uint32_t w, std::span<const uint8_t> watching) const;
  void sort_matches(uint32_t w, WatchStepOutput& out) const;
  void share_neighbor_values(State& state);
  void queue_actions(State& state, const StepOutput& out);
  void start_thread(unsigned thread, const State& state);
  void run_blocks(unsigned thread, std::span<const uint32_t> blocks, State& state);
  void run_over_ranks(State& state);
  void split_own_blocks(const State& state);
  std::vector<std::vector<std::byte>> batches_for_ranks();
  void open_batches();
  void run_programs(unsigned thread, uint32_t begin, uint32_t end, const State& state);
  void run_agents(unsigned thread, uint32_t block, uint32_t watch, State& state);
  void step_block_agents(unsigned thread, uint32_t block, uint32_t watch, WatchState& ws, int64_t f);
  void finish_distributed(uint32_t watch, State& state, WatchStepOutput& out, int64_t f);
  void observe_detector(uint32_t watch, State& state, WatchStepOutput& out);
  void deliver_program_messages(State& state);
  void take_arrived_lanes(uint32_t watch, WatchState& ws);
  std::vector<std::span<const int64_t>> gather_values(const State& state, Gathered& parts);
  uint64_t pass_hash(uint64_t h, const std::function<uint64_t(uint64_t, uint32_t, uint32_t)>& run);
  void add_up_over_ranks(watch::AgentStepOutcome& outcome);
  void agree_on_failure_and_gather_actuations(int64_t step);

  uint32_t block_begin(uint32_t block) const;  // its first module; block_begin(blocks_) = module count
  void place_blocks(Partition partition);      // owners_.block_rank and own_blocks_

  const Model& model_;
  World& world_;
  WorkerPool pool_;
  uint32_t blocks_ = 0;
  RankExchange* ranks_;               // null: this process runs every module
  ModuleOwners owners_;               // blocks of 1 << owners_.block_shift modules, and the rank that steps each
  std::vector<uint32_t> own_blocks_;  // this rank's, ascending; thread t takes the t-th of equal runs
  uint32_t first_ = 0, window_ = 0;   // the modules the state holds (module_window)
  uint64_t bytes_to_ranks_ = 0;
  double world_seconds_ = 0;
  Partition partition_;
  // This step's own blocks that may send to another rank, which run first so that their batches
  // travel while the others (interior) run; and what they are worked out from, per graph sent
  // along (the programs' N(m, t), each watch's agents' N(m, t - E+)): per own block, whether a
  // module of it has a neighbour on another rank. Keeping the graph keeps its identity unique.
  std::vector<uint32_t> border_blocks_, interior_blocks_;
  struct Border {
    std::shared_ptr<const void> graph;
    std::vector<uint8_t> crosses;
  };
  std::vector<Border> borders_;
  bool exchanging_ = false;                      // thread 0 lets the exchange on between blocks
  std::vector<size_t> border_messages_;          // per thread: its outbox's messages from border blocks
  std::vector<std::vector<std::byte>> arrived_;  // this step's batches from the other ranks
  std::vector<Messages> arrived_messages_;       // per rank
  std::vector<std::vector<std::span<const std::byte>>> arrived_lanes_;  // per watch, per rank
  std::vector<ThreadScratch> scratch_;
  std::vector<const HostProgram*> programs_;  // in use, by index: the model's unless replaced
  std::vector<int64_t> next_values_;
  std::vector<std::vector<int>> columns_;                    // per watch: program variable -> model column
  std::vector<std::vector<watch::RecordBuffer>> sending_;    // per watch: lanes being filled
  std::vector<uint32_t> counts_;                             // for gathering messages
  std::vector<uint32_t> agent_watches_;                      // this step: watchpoints whose agents run
  std::vector<std::vector<watch::RecordBuffer*>> arriving_;  // per thread: a block's lanes
  std::vector<Actuation> actuations_;                        // the step's, for the world
};

}  // namespace dw::sim
