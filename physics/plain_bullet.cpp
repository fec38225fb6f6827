#include "physics/plain_bullet.h"

#include <algorithm>
#include <chrono>
#include <memory>

#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btDefaultCollisionConfiguration.h>
#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btCompoundShape.h>
#include <BulletCollision/CollisionShapes/btStaticPlaneShape.h>
#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

#include "physics/convert.h"
#include "physics/shapes.h"
#include "physics/warm_start.h"

namespace dw::physics {

PlainRun run_plain_bullet(const PlainScene& scene, const PhysicsSettings& settings, Sleeping sleeping, int64_t steps) {
  // Declared in the order that tears them down safely: the world goes first (it unlinks the
  // bodies), then the bodies, then their shapes.
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher(&config);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  const std::unique_ptr<btCollisionShape> module = make_module_shape(ModuleShape::Box);  // dwatch's own box
  btCollisionShape& box = *module;
  btStaticPlaneShape ground(btVector3(0, 0, 1), scene.ground_z);
  std::vector<std::unique_ptr<btCompoundShape>> compounds;
  std::vector<std::unique_ptr<btRigidBody>> rigid;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &config);
  // How long a body is still before it sleeps is Bullet's global (2 s unless set): this runs in a
  // process of its own (bench_physics.cpp).
  if (sleeping == Sleeping::AsBullet) gDeactivationTime = settings.sleep_after;
  world.setGravity(to_bt(settings.gravity));
  world.getSolverInfo().m_numIterations = settings.solver_iterations;
  world.getSolverInfo().m_solverMode = kSolverMode;  // dwatch's (physics/warm_start.h)

  const auto add = [&](float mass, btCollisionShape* shape, const btTransform& pose) {
    btVector3 inertia(0, 0, 0);
    if (mass > 0) shape->calculateLocalInertia(mass, inertia);
    btRigidBody::btRigidBodyConstructionInfo info(mass, nullptr, shape, inertia);
    info.m_startWorldTransform = pose;
    info.m_friction = settings.friction;
    info.m_restitution = settings.restitution;
    btRigidBody* body = rigid.emplace_back(std::make_unique<btRigidBody>(info)).get();
    if (sleeping == Sleeping::Never) body->setActivationState(DISABLE_DEACTIVATION);
    else body->setSleepingThresholds(settings.sleep_linear, settings.sleep_angular);
    world.addRigidBody(body);
  };
  btTransform identity;
  identity.setIdentity();
  add(0, &ground, identity);
  // A cluster is a compound about its boxes' centroid (their centre of mass: every box weighs
  // the same), its inertia Bullet's own estimate from its bounds (exact for a full block).
  for (const PlainBody& b : scene.bodies) {
    const float mass = b.fixed ? 0.0f : settings.module_mass * float(b.boxes.size());
    if (b.boxes.size() == 1) {
      add(mass, &box, to_bt(b.boxes[0]));
      continue;
    }
    btVector3 centre(0, 0, 0);
    for (const sim::Pose& p : b.boxes) centre += to_bt(p.position);
    centre /= btScalar(b.boxes.size());
    auto& compound = compounds.emplace_back(std::make_unique<btCompoundShape>(true, int(b.boxes.size())));
    for (const sim::Pose& p : b.boxes) {
      btTransform local = to_bt(p);
      local.setOrigin(local.getOrigin() - centre);
      compound->addChildShape(local, &box);
    }
    add(mass, compound.get(), btTransform(btQuaternion::getIdentity(), centre));
  }

  PlainRun run;
  const auto since = [](std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  // Each step as fixed substeps, as dwatch makes them (one call of stepSimulation(dt, substeps,
  // dt / substeps) rounds its leftover time into the next step): as many as the fastest body
  // awake needs (substeps_for), for the whole world — dwatch gives them to its islands apart.
  const btScalar dt = settings.dt, fall = to_bt(settings.gravity).length() * dt * dt;
  for (int64_t s = 0; s < steps; ++s) {
    const auto start = std::chrono::steady_clock::now();
    btScalar fastest = 0;
    for (const auto& body : rigid)
      if (body->isActive() && !body->isStaticObject()) {
        btVector3 centre;
        btScalar radius;
        body->getCollisionShape()->getBoundingSphere(centre, radius);
        fastest = std::max(fastest, body->getLinearVelocity().length() * dt + fall +
                                        body->getAngularVelocity().length() * dt * (centre.length() + radius));
      }
    const int substeps = substeps_for(settings, float(fastest));
    const btScalar substep = dt / btScalar(substeps);
    for (int k = 0; k < substeps; ++k) world.stepSimulation(substep, 0, substep);
    (s == 0 ? run.first_step_seconds : run.later_steps_seconds) += since(start);
  }

  // Each box where its body put it, its centre moving with the body's velocity at that point.
  for (size_t i = 0; i < scene.bodies.size(); ++i) {
    const btRigidBody& body = *rigid[i + 1];  // after the ground
    const btTransform& frame = body.getWorldTransform();
    const auto* compound =
        scene.bodies[i].boxes.size() == 1 ? nullptr : static_cast<const btCompoundShape*>(body.getCollisionShape());
    for (size_t k = 0; k < scene.bodies[i].boxes.size(); ++k) {
      const btVector3 centre = compound ? frame(compound->getChildTransform(int(k)).getOrigin()) : frame.getOrigin();
      const btVector3 linear =
          body.getLinearVelocity() + body.getAngularVelocity().cross(centre - body.getCenterOfMassPosition());
      run.boxes.push_back(
          {scene.bodies[i].boxes[k].position, from_bt(centre), from_bt(linear), from_bt(body.getAngularVelocity())});
    }
  }
  return run;
}

}  // namespace dw::physics
