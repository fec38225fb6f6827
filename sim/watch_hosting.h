// Hosting the watchpoints on the runtime (docs/design.md §4, §4b, §12): each one's detector, which
// either observes the frame of every step in one place (centralized, or over simultaneous states)
// or runs as agents on the modules, stepped block by block on the runtime's threads beside the
// programs (the paper's distributed algorithm); the matches each decides in a step, in a fixed
// order, and the actions they queue for the next.
//
// The runtime steps the agents in this order: begin_step, then on each thread start_thread and
// run_block for each of its blocks, then (the step assigned) finish_step and queue_actions.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sim/block_placement.h"
#include "sim/model.h"
#include "sim/rank_exchange.h"
#include "sim/state.h"
#include "sim/world.h"
#include "watch/agent_step.h"

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

// The frame the watchpoints see of a step: the variables (of the modules from `first_module` on;
// all of them but over ranks), presence and N(m, step) (lent, see Frame::topology).
watch::Frame make_frame(const Model& model, int64_t step, std::span<const int64_t> values,
                        std::span<const uint8_t> present, const std::shared_ptr<const NeighborGraph>& graph,
                        uint32_t first_module = 0);

// Why `watches` (a model's) cannot run over several ranks, or empty when they can (docs/design.md
// §12): a centralized or simultaneous-state detector observes the whole ensemble in one place,
// which no rank holds.
std::string why_not_over_ranks(std::span<const HostedWatchpoint> watches);
inline std::string why_not_over_ranks(const Model& model) { return why_not_over_ranks(model.watches); }

// Why the whole run's PatternMatcher budget (`limit`, watch::RunBudget) stops a watchpoint `when`
// ("at step 5"): it passed it with those charged before it, or (`already`) they had passed it.
std::string over_run_budget(bool already, uint64_t limit, std::string_view when);
// What a watchpoint's stop says wherever it is told (`run`, `replay`, the session's answers): its
// `reason` with the figure, that the matches found before are kept, and what raises the budget
// that stopped it: the run's names --max-live-all in its reason, its own is `own_budget`.
std::string stop_text(const std::string& reason, std::string_view own_budget);

// PatternMatchers another rank sent to one of this rank's blocks: records for its first lane.
struct ArrivedLane {
  uint32_t block = 0;
  std::span<const std::byte> records;
};

class WatchHosting {
 public:
  // Hosts `watches` for the modules `placement` gives this process, on `threads` threads, over
  // `ranks` when given. The model, the watches and the placement must outlive the hosting; the
  // runtime is made again when the watches change.
  WatchHosting(const Model& model, HostedWatches watches, const BlockPlacement& placement, unsigned threads,
               RankExchange* ranks);

  uint32_t size() const { return static_cast<uint32_t>(watches_.size()); }
  // A fresh detector state for watchpoint w, as before step 0.
  WatchState initial_state(uint32_t w) const;
  // Whether watchpoint w observes a step when `watching` marks those asked for (all when empty):
  // one with actions always does, its actions being part of the simulation.
  bool observes(uint32_t w, std::span<const uint8_t> watching) const;

  // Before the threads run state.step: the watchpoints whose agents run it (agent_watches) make
  // room for it in their history; `next_values` are where the threads put the step's variables.
  void begin_step(State& state, std::span<const uint8_t> watching, std::span<const int64_t> next_values);
  std::span<const uint32_t> agent_watches() const { return agent_watches_; }
  // Each agent watch's N(m, t - E+), along which its agents send this step, with what keeps it
  // (its identity); none for a watch whose history holds no graph of that step.
  struct SendingGraph {
    std::shared_ptr<const void> owner;
    watch::AgentHistory::StepGraph graph;
  };
  std::vector<SendingGraph> sending_graphs(const State& state) const;
  // A thread's part of the step: its agent contexts made ready, then block by block (after the
  // block's programs) each agent watch's agents record the block's modules and take their step.
  void start_thread(unsigned thread, int64_t step);
  void run_block(unsigned thread, uint32_t block, State& state, std::span<const int64_t> next_values);
  // Whether an agent watch of this step reads the step's snapshot (watch::reads_step_snapshot): its
  // agents only record in run_block, and take their step in run_late_block, block by block, once
  // every block has recorded (and, over ranks, every rank's values are in).
  bool late_agents() const;
  void run_late_block(unsigned thread, uint32_t block, State& state);
  // The step assigned (state.values hold its variables): each watchpoint that observes it decides
  // its matches into out[w], in a fixed order whatever the threads and ranks; `arrived` are the
  // PatternMatchers other ranks sent, per watch (none in one process).
  void finish_step(State& state, std::span<WatchStepOutput> out, std::span<const uint8_t> watching,
                   std::span<const std::vector<ArrivedLane>> arrived);
  // The actions of the matches decided this step, due at the start of the next (State::actions).
  void queue_actions(State& state, std::span<const WatchStepOutput> out) const;
  // The whole run's PatternMatcher budget (watch::RunBudget): the next step charges `others` ahead
  // of the watchpoints without actions it runs, in place of those not run, when a session steps one
  // alone over its history (the total the run was charged at that step, which holds theirs); each
  // step charges from nothing otherwise. Then what the step was charged in all (its watchpoints
  // with actions first, then the others, each in position order), for the session to keep.
  void charge_before(std::optional<uint64_t> others) { others_ = others; }
  uint64_t charged() const { return charged_; }
  // The actions due at the start of this step, carried out on the state (and the world, for a
  // removal), in the order queued.
  void act(State& state, World& world) const;
  // Over ranks, the step's variables of every rank written into the history of the agents that read
  // their neighbours' (an aggregate's): a collective call.
  void share_neighbor_values(State& state);
  // Over ranks, before run_late_block: the step's variables of every rank (`values`, this rank's
  // window of them) written into the history of the agents that read the step's snapshot.
  void share_step_values(State& state, std::span<const int64_t> values);

  // The run is over: detector step f of watchpoint w's agents, from the history they hold
  // (Runtime::drain_agents). drain_begin, then drain_blocks on each thread, then drain_finish.
  void drain_begin(uint32_t w);
  void drain_blocks(unsigned thread, uint32_t w, int64_t f, State& state);
  void drain_finish(State& state, uint32_t w, int64_t f, WatchStepOutput& out,
                    std::span<const std::vector<ArrivedLane>> arrived);

  // Watch w's PatternMatcher lanes being filled: [sending thread * blocks + receiving block].
  std::span<watch::RecordBuffer> lanes(uint32_t w) { return sending_[w]; }

 private:
  struct Lanes;  // a thread's PatternMatcher outbox

  void step_block_agents(unsigned thread, uint32_t block, uint32_t w, WatchState& ws, int64_t f);
  void finish_distributed(uint32_t w, State& state, WatchStepOutput& out, int64_t f,
                          std::span<const ArrivedLane> arrived, bool whole_run = false);
  void observe_detector(uint32_t w, State& state, WatchStepOutput& out);
  // Charges watchpoint w's step, which wanted `wanted` live PatternMatchers and messages (at least
  // that many when a context was held back): why the run's budget stops it, or "".
  std::string run_budget_verdict(uint32_t w, uint64_t wanted);
  void stop(WatchState& ws, uint32_t w, std::string why);
  void sort_matches(uint32_t w, WatchStepOutput& out) const;
  void take_arrived_lanes(WatchState& ws, std::span<const ArrivedLane> arrived) const;
  void share_values(State& state, std::span<const int64_t> values, bool late);
  void gather_whole_graph(const State& state);
  // The neighbour graph watch w's agents record: the rank's window of it, or every module's.
  const std::shared_ptr<const NeighborGraph>& agent_graph(uint32_t w, const State& state) const;

  const Model& model_;
  HostedWatches watches_;
  const BlockPlacement& placement_;
  const unsigned threads_;
  RankExchange* ranks_;                                     // null: one process
  std::vector<std::vector<watch::AgentContext>> contexts_;  // per thread, per watch (distributed ones used)
  std::vector<std::vector<int>> columns_;                   // per watch: program variable -> model column
  std::vector<uint8_t> snapshot_;                           // per watch: its agents step late (late_agents)
  std::vector<uint8_t> far_lists_;  // per watch: over ranks, its agents read every module's list (agent_graph)
  std::shared_ptr<const NeighborGraph> whole_graph_, whole_of_;  // every module's lists, and the window they
                                                                 // were gathered from
  std::vector<std::vector<watch::RecordBuffer>> sending_;        // per watch: lanes being filled
  std::vector<uint32_t> agent_watches_;                          // this step: watchpoints whose agents run
  std::vector<std::vector<watch::RecordBuffer*>> arriving_;      // per thread: a block's lanes
  // The whole run's budget: the watchpoints in charging order (those with actions first, whose
  // stops are part of the simulation and a re-simulation steps alone), each one's place in it, and
  // per thread and watch what its context charged this step.
  std::vector<uint32_t> charging_order_, charged_at_;
  watch::RunBudget run_budget_;
  std::vector<std::vector<uint64_t>> published_;
  uint32_t acting_count_ = 0;  // the watchpoints with actions, charged first
  std::optional<uint64_t> others_;
  int64_t step_ = 0;
  bool draining_ = false;  // a drain since the last step: the session charges it the run's budget whole
  uint64_t charged_ = 0;   // this step's running total, in charging order
  bool passed_ = false;    // this step passed the run's budget: the watchpoints charged after stop
};

}  // namespace dw::sim
