#include "sim/world.h"

namespace dw::sim {

void StaticLatticeWorld::initialize(const Model& model, State& state) {
  if (!graph_) graph_ = std::make_shared<const NeighborGraph>(model.lattice.graph);
  state.present.assign(model.module_count(), 1);
  state.graph = graph_;
}

}  // namespace dw::sim
