#include "sim/world.h"

namespace dw::sim {

void StaticLatticeWorld::initialize(const Model& model, State& state) {
  if (!graph_) graph_ = std::make_shared<const NeighborGraph>(model.lattice.graph);
  state.present = model.lattice.occupied;
  state.graph = graph_;
}

}  // namespace dw::sim
