#include "sim/world.h"

namespace dw::sim {

void World::remove_module(const Model&, State& state, ModuleId m) {
  if (!state.present[m]) return;
  state.present[m] = 0;
  state.graph = std::make_shared<const NeighborGraph>(state.graph->without(m));
}

void StaticLatticeWorld::initialize(const Model& model, State& state, WorkerPool&) {
  state.present = model.lattice.occupied;
  state.graph = model.lattice.graph;
}

}  // namespace dw::sim
