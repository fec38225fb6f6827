// The parts of a dynamics step (physics/dynamics.h) that its stages share across files:
// dynamics.cpp plans a step and settles it, dynamics_world.cpp steps a batch of islands in a
// Bullet world. Private to them.
#pragma once

#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btDefaultCollisionConfiguration.h>
#include <BulletCollision/CollisionShapes/btCompoundShape.h>
#include <BulletCollision/CollisionShapes/btStaticPlaneShape.h>
#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h>
#include <LinearMath/btPoolAllocator.h>

#include "physics/box_plane.h"
#include "physics/dynamics.h"
#include "physics/shapes.h"

namespace dw::physics {

// A cluster's shape: its members' shapes at their local poses, and its principal inertia.
struct Dynamics::Compound {
  std::vector<sim::Pose> local;  // the key, compared in full: a hash alone could collide
  std::unique_ptr<btCompoundShape> shape;
  std::vector<uint32_t> member_of_child;  // child i of `shape` is member member_of_child[i]
  btVector3 inertia;
  int64_t used = 0;
};

// Bullet's collision configuration and dispatcher, with pools of `pool` manifolds and as many
// collision algorithms: what a world gets beyond them comes from the heap, one allocation each.
struct Dynamics::Collision {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  BoxPlaneCreateFunc box_plane{false}, plane_box{true};
  explicit Collision(int pool) : config(pool_sizes(pool)) {
    dispatcher.registerCollisionCreateFunc(BOX_SHAPE_PROXYTYPE, STATIC_PLANE_PROXYTYPE, &box_plane);
    dispatcher.registerCollisionCreateFunc(STATIC_PLANE_PROXYTYPE, BOX_SHAPE_PROXYTYPE, &plane_box);
    // A box on the ground gets all its corners in one query (physics/box_plane.h); other shapes
    // a few points a query, tilted, and the rest from the contact cache over steps
    // (physics/warm_start.h).
    config.setPlaneConvexMultipointIterations();
    config.setConvexConvexMultipointIterations();
  }
  static btDefaultCollisionConstructionInfo pool_sizes(int pool) {
    btDefaultCollisionConstructionInfo info;
    info.m_defaultMaxPersistentManifoldPoolSize = pool;
    info.m_defaultMaxCollisionAlgorithmPoolSize = pool;
    return info;
  }
  // Whether the pools hold `manifolds` manifolds and the algorithms of `pairs` pairs (a cluster's
  // pair has one more for each child it touches: a full algorithm pool says so).
  bool holds(int manifolds, int pairs) {
    return manifolds < config.getPersistentManifoldPool()->getMaxCount() &&
           pairs < config.getCollisionAlgorithmPool()->getMaxCount() &&
           config.getCollisionAlgorithmPool()->getFreeCount() > 0;
  }
};

// Per worker thread: what Bullet would otherwise allocate, zero and free again for each island of
// each step, kept for the next (none of it is state: a world leaves it empty, and the results do
// not depend on it).
struct Dynamics::Worker {
  static constexpr int kFirstPool = 4096;  // Bullet's default
  std::unique_ptr<Collision> collision = std::make_unique<Collision>(kFirstPool);
  int pool = kFirstPool;
  int needed = 0;  // what an island needed beyond the pools, 0 if they sufficed
  // The broadphase, emptied by each world and reset to its first state before the next
  // (btDbvtBroadphase::resetPool: the pairs it finds, and their order, as a fresh one's).
  btDbvtBroadphase broadphase;
  // Reused by every island of the worker: its pools keep their memory (a fresh solver zeroed them
  // every step). Nothing of a solve outlives it but the seed of a random order, which is unused
  // and reset.
  btSequentialImpulseConstraintSolver solver;

  // Before an island: pools with room to spare for what one overflowed (so that a large pile's
  // every manifold comes from one block paged in once, not from the heap anew each step).
  Collision& fit() {
    if (needed > 0) {
      pool = int(std::bit_ceil(uint32_t(needed + needed / 4)));
      collision = std::make_unique<Collision>(pool);
      needed = 0;
    }
    broadphase.resetPool(&collision->dispatcher);
    return *collision;
  }
};

struct Dynamics::Shapes {
  std::vector<std::unique_ptr<Worker>> workers;
  std::unique_ptr<btCollisionShape> module;
  btStaticPlaneShape ground;
  std::vector<std::unique_ptr<btCollisionShape>> props;
  std::unordered_map<uint64_t, Compound> compounds;  // by a hash of the local poses

  Shapes(ModuleShape shape, float ground_z) : module(make_module_shape(shape)), ground(btVector3(0, 0, 1), ground_z) {}
};

// One body of a step, in tag order: ground -1, then clusters, movers, props.
struct Dynamics::Body {
  int tag = 0;
  float mass = 0;
  btCollisionShape* shape = nullptr;
  btVector3 inertia{0, 0, 0};
  btTransform pose, before;  // before: a kinematic body's last pose (Bullet takes its velocity from the two)
  sim::Velocity velocity;
  bool kinematic = false;
  ReachBox reach;    // where it can be over the step
  float travel = 0;  // how far a point of it can move over the step (speed, pushes and turning)
};

// What one step works from: its bodies in tag order (ground -1, then clusters, movers, props), the
// islands they form, each island's pushes, and which islands sleep.
struct Dynamics::Plan {
  int clusters = 0, movers = 0;
  std::vector<Body> bodies;
  std::vector<const Compound*> compound_of;  // per cluster of more than one module
  std::vector<std::vector<uint32_t>> islands;
  std::vector<std::vector<const Push*>> pushes;  // per island
  std::vector<uint8_t> asleep;                   // per island
  // Islands stepped together in one Bullet world: batch k is islands batches[k] to
  // batches[k + 1] (form_islands).
  std::vector<uint32_t> batches;
};

// What stepping one island wrote beside the bodies: contact forces on modules, and its contact
// points for the next step's warm start.
struct Dynamics::IslandOutput {
  std::vector<std::pair<sim::ModuleId, float>> forces;
  std::vector<sim::ContactPoint> contacts;
};

}  // namespace dw::physics
