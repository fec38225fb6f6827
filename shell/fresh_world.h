// A world of its own for a copy of a session (Python's Session.fork: two branches stepped side by
// side): the world a scenario's session steps holds state of its own between steps (Bullet's
// bodies, the contacts measured), so two sessions never share one.
#pragma once

#include <memory>

#include "scenarios/scenario.h"
#include "sim/world.h"

namespace dw::shell {

// A world like the scenario's as it was loaded (the same physics settings over the same lattice,
// or the static lattice), not yet stepped: a session copied onto it (sim::Session's copy) tells it
// the state before its first step.
std::unique_ptr<sim::World> fresh_world(const scenarios::Scenario& scenario);

}  // namespace dw::shell
