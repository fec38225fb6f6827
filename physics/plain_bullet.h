// The plain Bullet program `dwatch bench physics` sets dwatch's physics step beside (issue 60): one
// persistent btDiscreteDynamicsWorld (btDbvtBroadphase, btSequentialImpulseConstraintSolver,
// btDefaultCollisionConfiguration), stepped as a Bullet user steps it, with dwatch's settings
// (physics/settings.h): boxes one module across (Bullet's own margin, as physics/shapes.cpp
// makes them), the module mass, dt in as many substeps, gravity, friction, restitution, solver
// iterations and mode (physics/warm_start.h), the sleeping thresholds, and a static plane for the
// ground. It lives in physics/, where Bullet's headers may be seen (docs/design.md §1); no Bullet
// type is named here.
#pragma once

#include <cstdint>
#include <vector>

#include "physics/settings.h"
#include "sim/bodies.h"

namespace dw::physics {

// One rigid body of the scene: a box one module across, or a cluster of them held as one rigid
// compound; fixed (mass 0) or free.
struct PlainBody {
  std::vector<sim::Pose> boxes;  // each box's pose in the world at the start
  bool fixed = false;
};

struct PlainScene {
  std::vector<PlainBody> bodies;
  float ground_z = 0;  // the ground plane's height
};

// Whether bodies ever sleep: never (DISABLE_DEACTIVATION on every body), or as Bullet lets them:
// an island whose bodies have all been slower than the settings' sleeping thresholds for
// `sleep_after` seconds sleeps until something touches it.
enum class Sleeping { Never, AsBullet };
// What dwatch does with these settings (physics/settings.h: sleep_after 0, nothing sleeps).
inline Sleeping sleeping_of(const PhysicsSettings& settings) {
  return settings.sleep_after > 0 ? Sleeping::AsBullet : Sleeping::Never;
}

// Where one box started and ended, and how it moved at the end (its centre's velocity, and its
// body's angular velocity).
struct BoxMotion {
  sim::Vec3 start{}, end{};
  sim::Vec3 linear{}, angular{};
};

struct PlainRun {
  // In stepSimulation: the first step, which finds every pair of bodies whose bounds meet and
  // makes their manifolds, apart from the steps after it.
  double first_step_seconds = 0, later_steps_seconds = 0;
  std::vector<BoxMotion> boxes;  // every box of every body, in the scene's order
};

// Builds the scene in a fresh world and steps it `steps` times (the building untimed).
PlainRun run_plain_bullet(const PlainScene& scene, const PhysicsSettings& settings, Sleeping sleeping, int64_t steps);

}  // namespace dw::physics
