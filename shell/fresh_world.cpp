// A world of its own for a copy of a session (fresh_world.h).
#include "shell/fresh_world.h"

#include <stdexcept>

#include "physics/bullet_world.h"

namespace dw::shell {

std::unique_ptr<sim::World> fresh_world(const scenarios::Scenario& scenario) {
  if (const auto* physical = dynamic_cast<const physics::BulletWorld*>(scenario.world.get()))
    return std::make_unique<physics::BulletWorld>(physical->settings(), scenario.model->lattice);
  if (dynamic_cast<const sim::StaticLatticeWorld*>(scenario.world.get()))
    return std::make_unique<sim::StaticLatticeWorld>();
  throw std::logic_error("a world of a kind that fresh_world does not make");  // a scenario loads only these two
}

}  // namespace dw::shell
