// What a scenario fixes about the physics (docs/design.md §8): const for the run, beside the Model.
// Units: module sizes (1 m), kilograms, seconds; z is up and the ground lies under the lowest
// modules.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "sim/bodies.h"
#include "sim/lattice.h"

namespace dw::physics {

// Disc: a cylinder lying across the x-z plane (axis y), a 2-D catom of a vertical plane.
// HexPrism: an upright hexagonal prism (a Hexanode), its six faces towards hex2d's six neighbours.
enum class ModuleShape { Box, Cylinder, Sphere, Disc, HexPrism };
// Boxes for cubic and square2d, upright cylinders for hex2d, discs for hex2d_vertical, spheres for
// ring, line and fcc.
ModuleShape default_shape(sim::LatticeKind kind);

// A body that is not a module: a projectile, a ram, an obstacle. Touching it never makes a
// neighbour.
struct PropSpec {
  ModuleShape shape = ModuleShape::Sphere;  // Sphere or Box
  sim::Vec3 size{1, 1, 1};                  // a box's extents; a sphere's diameter is size[0]
  float mass = 1;                           // 0: fixed in place
  sim::Pose pose;
  sim::Velocity velocity;
};

struct PhysicsSettings {
  float dt = 1.0f / 60;
  sim::Vec3 gravity{0, 0, -9.81f};
  std::optional<ModuleShape> shape;  // default_shape(lattice kind) when unset
  float module_mass = 1;
  // Two modules are neighbours when their shapes are at most this far apart (docs/design.md §8). At most
  // kMaxContactThreshold, below which Bullet keeps contact points.
  float contact_threshold = 0.01f;
  // A double, as a scenario writes it: 0.015 itself is allowed (the float nearest it is below it).
  static constexpr double kMaxContactThreshold = 0.015;
  bool bonds = true;   // modules touching at the start are latched together
  bool anchor = true;  // modules touching the ground at the start are latched to it
  // A module pushed by other bodies harder than this (newtons, summed over a step) loses every
  // bond; 0: bonds never break. The ground's support never breaks a bond.
  float break_force = 1000;
  float friction = 0.6f;
  float restitution = 0.1f;
  // Rolling resistance of round modules (spheres, cylinders, discs), which Bullet's round bodies
  // lack: a free disc set rolling rolls for ever, and a pile of six rolls apart. As Bullet's
  // rolling friction (btCollisionObject::setRollingFriction): at each contact of a round module,
  // the torque against its rolling is at most this lever (m) times the contact's normal force,
  // and against spinning about the contact's normal at most `spinning_friction` times it (only
  // where rolling_friction > 0). Boxes and prisms tip rather than roll, and props keep none.
  float rolling_friction = 0.02f;   // m
  float spinning_friction = 0.02f;  // m
  int solver_iterations = 10;
  // Each step is solved as this many substeps of dt / substeps: a 200 kg box on a 1 kg cube stays
  // within 0.01 of rest and a column of ten boxes within 0.003 with 4 (1: 0.09 and 0.03 with 20
  // iterations) — substeps stiffen contacts where more iterations only converge slowly.
  int substeps = 4;
  // A batch of islands with a faster body is solved in more substeps, so that no body moves more
  // than `substep_travel` in one (up to `max_substeps`): a 200 kg ball at 14 m/s moves 0.058 in a
  // quarter of a 60th of a second, and the modules it strikes go that far into the next before
  // the solver sees the contact. Only what flies pays: a resting pile keeps `substeps`.
  float substep_travel = 0.0125f;  // m
  int max_substeps = 16;
  // Bullet's deactivation (btRigidBody, gDeactivationTime): a body slower than these for this long,
  // with every body of its island, sleeps — kept still, not stepped — until something awake could
  // reach it; the time is counted in the state (sim::Cluster::still). 0: nothing sleeps. Props
  // never sleep.
  float sleep_after = 2.0f;                         // seconds
  float sleep_linear = 0.8f, sleep_angular = 1.0f;  // m/s, rad/s
  int64_t move_steps = 30;                          // steps a lattice move takes
  std::vector<PropSpec> props;
};

// The substeps a step is solved in when its fastest body can move `travel` (a point of it, over
// the step): enough for none to move more than substep_travel in one, within [substeps,
// max_substeps].
inline int substeps_for(const PhysicsSettings& settings, float travel) {
  const int most = std::max(settings.max_substeps, settings.substeps);
  const float wanted = std::ceil(travel / settings.substep_travel);
  return !(wanted < float(most)) ? most : std::max(settings.substeps, int(wanted));
}

}  // namespace dw::physics
