// Warm starting from the contact cache (docs/design.md §8a). Each step's Bullet world starts with
// empty manifolds, so the points its narrow phase finds are new to it; before the solver runs, each is
// matched with the point of the same two modules that the last step left in the cache (the nearest
// within Bullet's contact breaking threshold, as btPersistentManifold::getCacheEntry matches), and
// starts from that point's accumulated impulses, friction directions and age. After the step, the
// points the solver worked on become the cache of the next. Bullet's own persistent manifolds do
// the same within one long-lived world; here the cache is state, so a seek, a thread count or a
// rank count sees the same warm start.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>

#include "sim/contact_cache.h"

namespace dw::physics {

// Which module (sim::ContactPoint::a, b: a module's id, the ground, a prop) a side of a contact
// point belongs to, from its collision object and the child shape it lies on (-1 for a shape that
// is not a compound); -1 when that does not say (a compound's child not given).
using ContactSide = std::function<int64_t(const btCollisionObject*, int child)>;

// The solver's mode: warm-started, two friction directions per point, fixed by the normal rather
// than by the sliding velocity and kept with the point (so that the impulses carried from step to
// step keep pointing where they were applied). The plain Bullet peer of `dwatch bench physics`
// solves with the same (physics/plain_bullet.h).
inline constexpr int kSolverMode = SOLVER_USE_WARMSTARTING | SOLVER_SIMD | SOLVER_USE_2_FRICTION_DIRECTIONS |
                                   SOLVER_DISABLE_VELOCITY_DEPENDENT_FRICTION_DIRECTION |
                                   SOLVER_ENABLE_FRICTION_DIRECTION_CACHING;

// A dynamics world whose solver (kSolverMode) starts from the contact cache (sorted by pair,
// sim/contact_cache.h). A step in substeps warm-starts its first from the cache and the others
// from Bullet's own manifolds.
//
// The world may be kept from step to step (physics/dynamics_parts.h, BatchWorld), so what it
// computes must not depend on what it did before: each step starts from empty manifolds
// (begin_step), and the solver takes the manifolds that have points in one order fixed by their
// bodies and children (solved()), not in the order Bullet happened to make them — nor by
// Bullet's islands, whose union of overlapping pairs and their ids depend on that history. The
// solution of a body does not depend on how its independent neighbours are grouped: no island
// is split by the order, each body sees its own contacts in the same order.
class WarmStartedWorld final : public btDiscreteDynamicsWorld {
 public:
  WarmStartedWorld(btDispatcher* dispatcher, btBroadphaseInterface* broadphase, btConstraintSolver* solver,
                   btCollisionConfiguration* config);
  // Before a step: every manifold emptied (their points are in `cache`, which the next substep
  // warm-starts from), and whose module each side of a contact is.
  void begin_step(std::span<const sim::ContactPoint> cache, ContactSide side);
  void solveConstraints(btContactSolverInfo& info) override;
  // The manifolds the solver worked on in the last substep, in its order.
  std::span<btPersistentManifold* const> solved() const { return solved_; }
  // The points of every manifold after the step, in the dispatcher's order (each pair's in the
  // order the solver saw them), appended to `out`.
  void keep_contacts(std::vector<sim::ContactPoint>& out);

 private:
  void warm_start();

  std::span<const sim::ContactPoint> cache_;
  ContactSide side_;
  bool started_ = false;  // a substep after the first continues from Bullet's own manifolds
  std::vector<btPersistentManifold*> solved_;
};

}  // namespace dw::physics
