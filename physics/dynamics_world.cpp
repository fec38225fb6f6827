// Stepping one batch of islands in its Bullet world (physics/dynamics.h): the world kept from the
// last step or made, its bodies made from the plan, warm-started from the contact cache
// (physics/warm_start.h), stepped in substeps, and what it moved written back.
#include <algorithm>

#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

#include "physics/convert.h"
#include "physics/dynamics_parts.h"
#include "physics/pair_cache.h"
#include "physics/warm_start.h"

namespace dw::physics {

// The module (or -1: a prop, the ground) a side of a contact lies on.
int64_t Dynamics::module_of(const Plan& plan, const sim::Bodies& b, const btCollisionObject* o, int child) {
  const int tag = o->getUserIndex();
  if (tag < 0 || tag >= plan.clusters + plan.movers) return -1;
  if (tag >= plan.clusters) return b.movers[size_t(tag - plan.clusters)].module;
  const sim::Cluster& c = b.clusters[size_t(tag)];
  if (c.count == 1) return b.members[c.first];
  // The compound holds only the surface members: its children are numbered among those.
  const std::vector<uint32_t>& member_of_child = plan.compound_of[size_t(tag)]->member_of_child;
  if (child < 0 || size_t(child) >= member_of_child.size()) return -1;
  return b.members[c.first + member_of_child[size_t(child)]];
}

std::vector<uint32_t> Dynamics::awake_bodies(const Plan& plan, uint32_t from, uint32_t to) {
  std::vector<uint32_t> bodies;
  for (uint32_t i = from; i < to; ++i)
    if (!plan.asleep[i]) bodies.insert(bodies.end(), plan.islands[i].begin(), plan.islands[i].end());
  std::sort(bodies.begin(), bodies.end());
  bodies.erase(std::unique(bodies.begin(), bodies.end()), bodies.end());
  return bodies;
}

// Keyed by the batch's first body that moves (one island holds it: no other batch of the step
// has it); a batch with none (never made by form_islands) has a key no body has.
std::unique_ptr<Dynamics::BatchWorld>& Dynamics::world_of(const Plan& plan, std::span<const uint32_t> bodies,
                                                          uint32_t batch) {
  const auto moving = std::find_if(bodies.begin(), bodies.end(),
                                   [&](uint32_t i) { return plan.bodies[i].mass > 0 || plan.bodies[i].kinematic; });
  const int key = moving != bodies.end() ? plan.bodies[*moving].tag : -2 - int(batch);
  return shapes_->worlds[key];
}

namespace {

// A body made anew where it stands in a world (as if just constructed from `info` and added): its
// place in the world and in the broadphase are kept, nothing else of its past.
void make_anew(btRigidBody& body, const btRigidBody::btRigidBodyConstructionInfo& info, const btVector3& gravity) {
  btBroadphaseProxy* proxy = body.getBroadphaseHandle();
  const int index = body.getWorldArrayIndex();
  body.~btRigidBody();
  new (&body) btRigidBody(info);
  body.setBroadphaseHandle(proxy);
  body.setWorldArrayIndex(index);
  if (!body.isStaticOrKinematicObject()) body.setGravity(gravity);  // as addRigidBody does
}

}  // namespace

// One batch of islands, [from, to), in its own Bullet world (kept from the last step when it holds
// the same bodies); it writes only its own clusters and props, and its forces and contacts into
// `out`.
void Dynamics::step_batch(const Plan& plan, uint32_t from, uint32_t to, std::span<const uint32_t> bodies,
                          std::unique_ptr<BatchWorld>& kept, btSequentialImpulseConstraintSolver& solver, int64_t step,
                          sim::Bodies& b, bool forces, IslandOutput& out) {
  std::vector<const Push*> pushes;
  for (uint32_t i = from; i < to; ++i)
    if (!plan.asleep[i]) pushes.insert(pushes.end(), plan.pushes[i].begin(), plan.pushes[i].end());
  const float dt = settings_.dt;
  const ContactSide side_of = [&](const btCollisionObject* o, int child) -> int64_t {
    const int tag = o->getUserIndex();
    if (tag < 0) return sim::kGroundContact;
    if (tag >= plan.clusters + plan.movers) return sim::contact_prop(uint32_t(tag - plan.clusters - plan.movers));
    return module_of(plan, b, o, child);
  };
  std::vector<BatchWorld::Member> members{{-1, 0, &shapes_->ground, false}};
  for (uint32_t i : bodies) {
    const Body& body = plan.bodies[i];
    members.push_back({body.tag, body.mass, body.shape, body.kinematic});
  }
  if (!kept || kept->members != members) {
    kept.reset();  // its pairs go before the new world's are made
    kept = std::make_unique<BatchWorld>();
    kept->members = std::move(members);
  }
  BatchWorld& batch = *kept;
  batch.used = step;
  WarmStartedWorld& world = batch.world;
  world.setGravity(to_bt(settings_.gravity));
  world.getSolverInfo().m_numIterations = settings_.solver_iterations;
  solver.reset();
  world.setConstraintSolver(&solver);
  world.begin_step(b.contacts, side_of);
  const int props_from = plan.clusters + plan.movers;
  const bool made = batch.rigid.empty();
  const auto place = [&](size_t k, float mass, btCollisionShape* shape, const btVector3& inertia,
                         const btTransform& pose, int tag) {
    btRigidBody::btRigidBodyConstructionInfo info(mass, nullptr, shape, inertia);
    info.m_startWorldTransform = pose;
    info.m_friction = settings_.friction;
    info.m_restitution = settings_.restitution;
    if (round_modules_ && tag >= 0 && tag < props_from) {  // a module's body: a cluster or a mover
      info.m_rollingFriction = settings_.rolling_friction;
      info.m_spinningFriction = settings_.spinning_friction;
    }
    if (made) batch.rigid.push_back(std::make_unique<btRigidBody>(info));
    else make_anew(*batch.rigid[k], info, world.getGravity());
    btRigidBody* body = batch.rigid[k].get();
    // Sleeping is the state's (Cluster::still, form_islands): Bullet's own would keep it outside.
    body->setActivationState(DISABLE_DEACTIVATION);
    body->setUserIndex(tag);
    if (made) world.addRigidBody(body);
    return body;
  };
  btTransform identity;
  identity.setIdentity();
  place(0, 0, &shapes_->ground, btVector3(0, 0, 0), identity, -1);
  std::vector<std::pair<int, btRigidBody*>> mine;  // (tag, body) of the bodies that move
  for (size_t k = 0; k < bodies.size(); ++k) {
    const Body& body = plan.bodies[bodies[k]];
    btRigidBody* r = place(k + 1, body.mass, body.shape, body.inertia, body.pose, body.tag);
    if (body.kinematic) {
      r->setCollisionFlags(r->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
      r->setInterpolationWorldTransform(body.before);
    } else if (body.mass > 0) {
      r->setLinearVelocity(to_bt(body.velocity.linear));
      r->setAngularVelocity(to_bt(body.velocity.angular));
      mine.emplace_back(body.tag, r);
    }
  }
  for (const Push* p : pushes) {  // `mine` is in tag order, a cluster's tag its index
    const int c = int(b.cluster_of[p->module]);
    btRigidBody* body =
        std::lower_bound(mine.begin(), mine.end(), c, [](const auto& x, int tag) { return x.first < tag; })->second;
    body->applyImpulse(to_bt(p->impulse), to_bt(b.poses[p->module].position) - body->getWorldTransform().getOrigin());
  }

  // Substeps of one fixed length, as many as the batch's fastest body needs (substeps_for: a
  // function of the state, its speeds at the step's start and its pushes, as the batches are),
  // each a step of its own (maxSubSteps 0: no interpolation). The contact force on a module over
  // the step (when `forces` asks for it) is what the solver applied over all of them, from other
  // bodies: the ground only carries what rests on it, its contacts do not count.
  float fastest = 0;
  for (uint32_t i : bodies) fastest = std::max(fastest, plan.bodies[i].travel);
  const int substeps = substeps_for(settings_, fastest);
  const float substep = dt / float(substeps);
  for (int k = 0; k < substeps; ++k) {
    world.stepSimulation(substep, 0, substep);
    // In the solver's order: a module's forces add up in the same order in every world.
    for (const btPersistentManifold* manifold : forces ? world.solved() : std::span<btPersistentManifold* const>{}) {
      if (manifold->getBody0()->getUserIndex() < 0 || manifold->getBody1()->getUserIndex() < 0) continue;
      for (int p = 0; p < manifold->getNumContacts(); ++p) {
        const btManifoldPoint& point = manifold->getContactPoint(p);
        const float f = float(point.getAppliedImpulse()) / dt;
        if (f <= 0) continue;
        if (const int64_t m = module_of(plan, b, manifold->getBody0(), point.m_index0); m >= 0)
          out.forces.emplace_back(sim::ModuleId(m), f);
        if (const int64_t m = module_of(plan, b, manifold->getBody1(), point.m_index1); m >= 0)
          out.forces.emplace_back(sim::ModuleId(m), f);
      }
    }
  }
  world.keep_contacts(out.contacts);

  for (const auto& [tag, body] : mine) {
    const sim::Pose pose = from_bt(body->getWorldTransform());
    const sim::Velocity velocity{from_bt(body->getLinearVelocity()), from_bt(body->getAngularVelocity())};
    if (tag < plan.clusters) {
      b.clusters[size_t(tag)].pose = pose;
      b.clusters[size_t(tag)].velocity = velocity;
    } else {
      b.prop_poses[size_t(tag - props_from)] = pose;
      b.prop_velocities[size_t(tag - props_from)] = velocity;
    }
  }
}

}  // namespace dw::physics
