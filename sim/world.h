// Where modules are and who touches whom (docs/design.md §2, §8). The runtime asks the world for the
// neighbour graph; a static lattice answers with its own, the Bullet world with its contacts.
// A world may hold state of its own (a physics engine's), which is why it is not in Model; it
// must be able to make that state agree with any State after a rollback.
#pragma once

#include <span>

#include "sim/actuation.h"
#include "sim/model.h"
#include "sim/rank_exchange.h"
#include "sim/state.h"
#include "sim/worker_pool.h"

namespace dw::sim {

class World {
 public:
  virtual ~World() = default;
  // Sets presence and N(m, 0) (and, for a physical world, poses) in the initial state. `workers`
  // are the runtime's threads, free while the world works; what the world computes with them must
  // not depend on their number.
  virtual void initialize(const Model& model, State& state, WorkerPool& workers) = 0;
  // Makes the world's own state agree with `state` (after a rollback).
  virtual void restore(const Model& model, const State& state) = 0;
  // Moves the world on by one step, after the programs of step state.step - 1 ran: carries out
  // what they asked of their bodies (in module order), then sets the presence, the bodies and
  // N(m, state.step) that the next step's programs see. A request the world cannot carry out
  // throws ProgramError.
  virtual void advance(const Model& model, State& state, std::span<const Actuation> actuations,
                       WorkerPool& workers) = 0;
  // An intervention (docs/design.md §7) before step state.step runs: module m leaves the ensemble. It is
  // absent from now on and out of N(·, state.step); a physical world also lets go of its body.
  virtual void remove_module(const Model& model, State& state, ModuleId m);
  // This process is one rank of a run over several (docs/design.md §12): every rank calls
  // advance alike, step by step, so a world may share its work among them through `ranks`
  // (collective calls), as long as every rank ends each step with the same state, but for
  // N(m, t), which a rank may hold for its window only (NeighborGraph::held): the modules it owns
  // and those within reach of them. `owners` says which rank owns each module: the work of a
  // module is best done by its owner.
  virtual void share_over(RankExchange* ranks, const ModuleOwners& owners) { (void)ranks, (void)owners; }
  // Whether N(m, t) changes as the run goes (bodies moving), beyond interventions: then the ids'
  // order says less about who will touch whom, and ranks share the modules by their graph.
  virtual bool moves() const { return false; }
};

// The lattice as laid out: every module present, the lattice's face adjacency for ever. Every
// state shares one graph.
class StaticLatticeWorld final : public World {
 public:
  void initialize(const Model& model, State& state, WorkerPool& workers) override;
  void restore(const Model&, const State&) override {}
  void advance(const Model&, State&, std::span<const Actuation>, WorkerPool&) override {}
};

}  // namespace dw::sim
