// Everything that changes during a run (docs/design.md §2): a snapshot is a copy of a State.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "sim/bodies.h"
#include "sim/message.h"
#include "sim/neighbor_graph.h"
#include "watch/detector.h"
#include "watch/distributed_agents.h"
#include "watch/record_buffer.h"

namespace dw::sim {

// What a watchpoint's match does at the start of step t + λ + 1 (docs/design.md §4b): set a module's
// variable, or take the module out.
struct PendingAction {
  uint32_t watch = 0;
  ModuleId module = 0;
  int32_t column = -1;  // set: the variable's column; -1 when the model has no such variable
  bool remove = false;
  bool known = false;  // set: the value is known
  int64_t value = 0;
  bool operator==(const PendingAction&) const = default;
};

// A hosted watchpoint's detector state.
struct WatchState {
  // Centralized: the detector, observing the whole ensemble once per step.
  std::unique_ptr<watch::Detector> detector;
  // Distributed: one agent per module, and the PatternMatchers in flight to be read at the
  // state's step, in lanes [sending thread * blocks + receiving block] (see WatchHosting).
  std::optional<watch::DistributedAgents> agents;
  std::vector<watch::RecordBuffer> in_flight;
  uint64_t matches = 0;
  uint64_t actions_done = 0, actions_skipped = 0;  // its matches' actions, carried out or not (docs/design.md §4b)
  bool stopped = false;                            // past the live budget: the watchpoint observes no more
  std::string stop_reason;

  WatchState() = default;
  WatchState(const WatchState& other);
  WatchState& operator=(const WatchState& other);
  WatchState(WatchState&&) = default;
  WatchState& operator=(WatchState&&) = default;
};

struct State {
  int64_t step = 0;                            // the next step to run; `values` are those of step - 1
  std::vector<int64_t> values;                 // [module * variables + column]
  std::vector<uint8_t> present;                // [module]
  std::shared_ptr<const NeighborGraph> graph;  // N(m, step): what the next step's programs see
  Bodies bodies;                               // poses, velocities, bonds (a physical world only)
  Mailbox inbox;                               // program messages to be read at `step`
  std::vector<PendingAction> actions;          // watchpoints' actions due at the start of `step`
  std::vector<WatchState> watches;
  uint64_t program_messages = 0;  // sent since step 0
  // The run hash (docs/design.md §7): the simulation hashes of every state this one followed on the
  // branch that led to it, chained (next_run_hash after each step); 0 before step 0.
  // Not part of the state hash: two runs may reach one state by different histories.
  uint64_t run_hash = 0;
};

// The state's simulation part with `values` for its variables: everything but the watchpoints'
// states, which are left empty (one per watchpoint), for simulating again (with the state's own
// values) or for putting a whole together from parts (with the values of all).
State simulation_part(const State& state, std::vector<int64_t> values);

// A state's hash, in two parts (docs/design.md §7): `simulation`, what the modules' programs and
// the world hold (step, variables, presence, topology, bodies, messages, actions due), and
// `watches`, what the watchpoints hold (detector state in flight, match and action counts). Two
// runs of one simulation under different watchpoints share `simulation`; `whole` covers both.
// PatternMatchers in flight are hashed as a multiset, since their order in the lanes depends on
// the thread count and nothing else does.
struct StateHash {
  uint64_t simulation = 0;
  uint64_t watches = 0;
  uint64_t run = 0;  // the state's run hash (State::run_hash), covering its history, not in whole()
  uint64_t whole() const;
  bool operator==(const StateHash&) const = default;
};
StateHash hash_state(const State& state);
// What hash_state takes of one watchpoint's PatternMatchers in flight: a sum of their hashes and
// their count, which add up over parts of the state (the ranks of a run, docs/design.md §12).
struct InFlightDigest {
  uint64_t sum = 0, count = 0;
};
InFlightDigest in_flight_digest(const WatchState& watch);
// The hash of a sequence the ranks hold in pieces (the variables, the bodies' per-module records,
// the inbox's messages), taken in module order without putting it together (docs/design.md §12):
// given the hash so far, returns it after the whole sequence, the same on every rank.
using PiecewiseHash = std::function<uint64_t(uint64_t h)>;
// What hash_state does with a run of each sequence: the hash `h` continued over it. The graph's
// and the bodies' runs are modules [first, end): each one's neighbours; each one's pose,
// velocity, pose in its cluster, cluster, bonds (to modules above it and to the ground) and
// lattice move.
uint64_t continue_hash(uint64_t h, std::span<const int64_t> values);
uint64_t continue_hash(uint64_t h, const NeighborGraph& graph, ModuleId first, ModuleId end);
uint64_t continue_hash(uint64_t h, const Bodies& bodies, ModuleId first, ModuleId end);
uint64_t continue_hash(uint64_t h, Messages messages);
// The sequences hash_state reads in pieces, each with its length: the variables (in module
// order), the modules' neighbours, their bodies (none without a physical world: `bodies` is then
// not called) and the inbox's messages (in the order one inbox holds them).
struct HashPieces {
  uint64_t value_count = 0;
  PiecewiseHash values;
  uint64_t graph_count = 0;  // modules, 0 for a state without a graph (`graph` not called)
  PiecewiseHash graph;
  uint64_t body_count = 0;
  PiecewiseHash bodies;
  uint64_t message_count = 0;
  PiecewiseHash messages;
};
// hash_state with each watchpoint's in-flight digest given rather than read from its lanes, and
// the sequences hashed by `pieces` in place of the state's own: a whole hashed from the ranks'
// parts.
StateHash hash_state(const State& state, std::span<const InFlightDigest> in_flight, const HashPieces& pieces);
// hash_state's simulation part alone, the sequences hashed by `pieces`: what the run hash chains.
uint64_t simulation_hash(const State& state, const HashPieces& pieces);
uint64_t simulation_hash(const State& state);
// The run hash after a step: run(t) = H(run(t - 1) ‖ simulation hash of the state after step t).
uint64_t next_run_hash(uint64_t run_before, uint64_t simulation);
// A state hash as the outputs print it: 0x and 16 hex digits.
std::string hash_text(uint64_t hash);
// All three as the outputs print them: "0xWHOLE (simulation 0x..., watchpoints 0x...)".
std::string hash_text(const StateHash& hash);

// The heap bytes a copy of the state holds, estimated from its sizes (the neighbour graph apart:
// states often share one).
size_t state_bytes(const State& state);
size_t graph_bytes(const NeighborGraph& graph);

}  // namespace dw::sim
