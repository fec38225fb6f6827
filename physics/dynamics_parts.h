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

#include "physics/box_plane.h"
#include "physics/dynamics.h"
#include "physics/pair_cache.h"
#include "physics/shapes.h"
#include "physics/warm_start.h"

namespace dw::physics {

// A cluster's shape: its members' shapes at their local poses, and its principal inertia.
struct Dynamics::Compound {
  std::vector<sim::Pose> local;  // the key, compared in full: a hash alone could collide
  std::unique_ptr<btCompoundShape> shape;
  std::vector<uint32_t> member_of_child;  // child i of `shape` is member member_of_child[i]
  btVector3 inertia;
  int64_t used = 0;
};

// One batch's Bullet world (docs/design.md §8a), kept from step to step while the batch is made
// of the same bodies: a 20^3 pile's hundred thousand pairs, collision algorithms and manifolds
// are not made and dropped again every step. None of it is state. Each step every body is made
// anew in place (as if just added) and every manifold emptied (WarmStartedWorld::begin_step), and
// the solver takes the manifolds in an order of their own: the step computes what a world built
// afresh from the state computes, whatever this one did before (a seek, a thread or a rank count
// sees the same).
struct Dynamics::BatchWorld {
  // What a body of the world is: a world is kept only while its bodies are the batch's.
  struct Member {
    int tag = 0;
    float mass = 0;
    const btCollisionShape* shape = nullptr;
    bool kinematic = false;
    bool operator==(const Member&) const = default;
  };
  // Bullet's small pools: a kept world makes its manifolds once, the rest come from the heap.
  static constexpr int kPool = 64;
  static btDefaultCollisionConstructionInfo pool_sizes() {
    btDefaultCollisionConstructionInfo info;
    info.m_defaultMaxPersistentManifoldPoolSize = kPool;
    info.m_defaultMaxCollisionAlgorithmPoolSize = kPool;
    return info;
  }

  btDefaultCollisionConfiguration config{pool_sizes()};
  btCollisionDispatcher dispatcher{&config};
  BoxPlaneCreateFunc box_plane{false}, plane_box{true};
  btDbvtBroadphase broadphase;
  std::vector<Member> members;
  std::vector<std::unique_ptr<btRigidBody>> rigid;  // outlive the world, which unlinks them when it goes
  // Its solver is the stepping worker's (step_batch): nothing of a solve outlives it but the
  // memory of its pools, which one worker's batches share.
  WarmStartedWorld world{&dispatcher, &broadphase, nullptr, &config};
  int64_t used = 0;  // the last step that stepped it

  BatchWorld() {
    dispatcher.registerCollisionCreateFunc(BOX_SHAPE_PROXYTYPE, STATIC_PLANE_PROXYTYPE, &box_plane);
    dispatcher.registerCollisionCreateFunc(STATIC_PLANE_PROXYTYPE, BOX_SHAPE_PROXYTYPE, &plane_box);
    // A box on the ground gets all its corners in one query (physics/box_plane.h); other shapes
    // a few points a query, tilted, and the rest from the contact cache over steps
    // (physics/warm_start.h).
    config.setPlaneConvexMultipointIterations();
    config.setConvexConvexMultipointIterations();
    world.getDispatchInfo().m_deterministicOverlappingPairs = true;
  }
  ~BatchWorld() { drop_all_pairs(*world.getPairCache(), dispatcher); }  // before the world goes
  BatchWorld(const BatchWorld&) = delete;
  BatchWorld& operator=(const BatchWorld&) = delete;
};

struct Dynamics::Shapes {
  // The batches' worlds, by the tag of a batch's first body that moves, and a solver for each
  // worker stepping them.
  std::unordered_map<int, std::unique_ptr<BatchWorld>> worlds;
  std::vector<std::unique_ptr<btSequentialImpulseConstraintSolver>> solvers;
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
