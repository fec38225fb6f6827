#include "physics/dynamics.h"
#include "physics/pair_cache.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btDefaultCollisionConfiguration.h>
#include <BulletCollision/CollisionShapes/btCompoundShape.h>
#include <BulletCollision/CollisionShapes/btStaticPlaneShape.h>
#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

#include "physics/convert.h"
#include "physics/shapes.h"

namespace dw::physics {

sim::Pose glide(const sim::Mover& mover, int64_t step) {
  const int64_t done = std::clamp<int64_t>(step - mover.start, 0, mover.steps);
  if (done == mover.steps) return mover.to;
  const float f = float(done) / float(mover.steps);
  sim::Pose p = mover.from;
  if (mover.angle == 0) {
    for (int i = 0; i < 3; ++i)
      p.position[i] = mover.from.position[i] + (mover.to.position[i] - mover.from.position[i]) * f;
    return p;
  }
  return turn(mover, f);
}

sim::Pose turn(const sim::Mover& pivot, float f) {
  const btVector3 axis = to_bt(pivot.axis), centre = to_bt(pivot.pivot);
  const btQuaternion arc(axis, pivot.angle * f), spin(axis, pivot.angle * pivot.spin * f);
  const btTransform from = to_bt(pivot.from);
  btTransform at(spin * from.getRotation(), centre + quatRotate(arc, from.getOrigin() - centre));
  return from_bt(at);
}

// A cluster's shape: its members' shapes at their local poses, and its principal inertia.
struct Dynamics::Compound {
  std::vector<sim::Pose> local;  // the key, compared in full: a hash alone could collide
  std::unique_ptr<btCompoundShape> shape;
  std::vector<uint32_t> member_of_child;  // child i of `shape` is member member_of_child[i]
  btVector3 inertia;
  int64_t used = 0;
};

struct Dynamics::Shapes {
  btDefaultCollisionConfiguration config;
  std::unique_ptr<btCollisionShape> module;
  btStaticPlaneShape ground;
  std::vector<std::unique_ptr<btCollisionShape>> props;
  std::unordered_map<uint64_t, Compound> compounds;  // by a hash of the local poses

  Shapes(ModuleShape shape, float ground_z)
      : config(), module(make_module_shape(shape)), ground(btVector3(0, 0, 1), ground_z) {
    // One query must give a resting contact all its points: nothing is kept to build them up
    // over several steps.
    config.setPlaneConvexMultipointIterations();
    config.setConvexConvexMultipointIterations();
  }
};

Dynamics::Dynamics(const PhysicsSettings& settings, ModuleShape shape, float ground_z)
    : settings_(settings), shapes_(std::make_unique<Shapes>(shape, ground_z)), module_shape_(shapes_->module.get()) {
  for (const PropSpec& p : settings.props) shapes_->props.push_back(make_prop_shape(p));
}

Dynamics::~Dynamics() = default;

bool Dynamics::idle(const sim::Bodies& b) const {
  // A module making a lattice move is kinematic: Bullet moves nothing for it against what is
  // anchored (the glide itself is the World's), so movers alone ask for no step.
  for (const sim::Cluster& c : b.clusters)
    if (!c.anchored) return false;
  for (const PropSpec& p : settings_.props)
    if (p.mass > 0) return false;
  return true;
}

std::vector<uint8_t> enclosed_boxes(const std::vector<sim::Pose>& members) {
  std::vector<uint8_t> inside(members.size(), 0);
  // Centres on a grid of 1/256 of a module: a neighbour found there is a neighbour; one missed by
  // rounding only keeps a member that could have gone.
  const auto cell = [](const btVector3& v) {
    const auto q = [](btScalar x) { return static_cast<int64_t>(std::llround(x * 256)); };
    return std::array<int64_t, 3>{q(v.x()), q(v.y()), q(v.z())};
  };
  struct CellHash {
    size_t operator()(const std::array<int64_t, 3>& c) const {
      return std::hash<int64_t>()(c[0] * 73856093 ^ c[1] * 19349663 ^ c[2] * 83492791);
    }
  };
  std::unordered_set<std::array<int64_t, 3>, CellHash> centres;
  for (const sim::Pose& p : members) centres.insert(cell(to_bt(p.position)));
  for (size_t i = 0; i < members.size(); ++i) {
    const btTransform pose = to_bt(members[i]);
    bool boxed = true;
    for (int axis = 0; axis < 3 && boxed; ++axis)
      for (btScalar side : {btScalar(-1), btScalar(1)}) {
        btVector3 step(0, 0, 0);
        step[axis] = side;  // the next cell across this face: lattice cells are one module apart
        if (!centres.count(cell(pose(step)))) {
          boxed = false;
          break;
        }
      }
    inside[i] = boxed;
  }
  return inside;
}

const Dynamics::Compound& Dynamics::compound(const sim::Bodies& b, const sim::Cluster& c, int64_t step) {
  uint64_t key = 0xcbf29ce484222325ull ^ c.count;
  for (uint32_t i = c.first; i < c.first + c.count; ++i) {
    const sim::Pose& p = b.local[b.members[i]];
    for (float x : p.position) key = (key ^ std::bit_cast<uint32_t>(x)) * 0x100000001b3ull;
    for (float x : p.orientation) key = (key ^ std::bit_cast<uint32_t>(x)) * 0x100000001b3ull;
  }
  auto same = [&](const Compound& k) {
    if (k.local.size() != c.count) return false;
    for (uint32_t i = 0; i < c.count; ++i)
      if (!(k.local[i] == b.local[b.members[c.first + i]])) return false;
    return true;
  };
  auto it = shapes_->compounds.find(key);
  while (it != shapes_->compounds.end() && !same(it->second)) it = shapes_->compounds.find(++key);
  if (it == shapes_->compounds.end()) {
    Compound k;
    btCompoundShape whole(true, static_cast<int>(c.count));
    for (uint32_t i = c.first; i < c.first + c.count; ++i) {
      k.local.push_back(b.local[b.members[i]]);
      whole.addChildShape(to_bt(k.local.back()), module_shape_);
    }
    std::vector<btScalar> masses(c.count, settings_.module_mass);
    btTransform principal;
    whole.calculatePrincipalAxisTransform(masses.data(), principal, k.inertia);
    // Collisions need only the members on the cluster's surface: nothing outside can reach one
    // boxed in on all six faces without passing through another first. The inertia above counts
    // every member; the ground, a prop or another cluster meets only the surface (a 20^3 cube:
    // 2,168 children, not 8,000, each tested against the ground every step).
    // Cylinders and spheres leave gaps between them: only boxes are left out.
    const std::vector<uint8_t> inside = module_shape_->getShapeType() == BOX_SHAPE_PROXYTYPE
                                            ? enclosed_boxes(k.local)
                                            : std::vector<uint8_t>(k.local.size(), 0);
    k.shape = std::make_unique<btCompoundShape>(true, static_cast<int>(c.count));
    for (uint32_t i = 0; i < c.count; ++i)
      if (!inside[i]) {
        k.shape->addChildShape(to_bt(k.local[i]), module_shape_);
        k.member_of_child.push_back(i);
      }
    it = shapes_->compounds.emplace(key, std::move(k)).first;
  }
  it->second.used = step;
  return it->second;
}

void Dynamics::step(sim::Bodies& b, std::span<const Push> pushes, int64_t to, std::vector<float>& force) {
  const float dt = settings_.dt;
  btDbvtBroadphase broadphase;
  btCollisionDispatcher dispatcher(&shapes_->config);
  btSequentialImpulseConstraintSolver solver;
  std::vector<std::unique_ptr<btRigidBody>> bodies;  // outlive the world, which unlinks them when it goes
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &shapes_->config);
  const PairsDroppedFirst<btDiscreteDynamicsWorld> teardown{world};
  world.setGravity(to_bt(settings_.gravity));
  world.getSolverInfo().m_numIterations = settings_.solver_iterations;
  // Warm starting stays on: its cache is empty in a fresh world, and only with it does the solver
  // write the applied impulses back to the contact points (read below for bond breaking).
  world.getDispatchInfo().m_deterministicOverlappingPairs = true;

  // A body's user index says what it is: ground -1, then clusters, movers, props.
  const int clusters = static_cast<int>(b.clusters.size()), movers = static_cast<int>(b.movers.size());
  auto add = [&](float mass, btCollisionShape* shape, const btVector3& inertia, const btTransform& pose, int tag) {
    btRigidBody::btRigidBodyConstructionInfo info(mass, nullptr, shape, inertia);
    info.m_startWorldTransform = pose;
    info.m_friction = settings_.friction;
    info.m_restitution = settings_.restitution;
    auto& body = bodies.emplace_back(std::make_unique<btRigidBody>(info));
    body->setActivationState(DISABLE_DEACTIVATION);  // sleeping changes contacts (docs/design.md §8)
    body->setUserIndex(tag);
    world.addRigidBody(body.get());
    return body.get();
  };
  btTransform identity;
  identity.setIdentity();
  add(0, &shapes_->ground, btVector3(0, 0, 0), identity, -1);

  std::vector<btRigidBody*> cluster_body(b.clusters.size());
  std::vector<const Compound*> cluster_compound(b.clusters.size(), nullptr);
  for (int i = 0; i < clusters; ++i) {
    const sim::Cluster& c = b.clusters[size_t(i)];
    btCollisionShape* shape = module_shape_;
    const float mass = c.anchored ? 0 : settings_.module_mass * float(c.count);
    btVector3 inertia(0, 0, 0);
    if (c.count > 1) {
      const Compound& k = compound(b, c, to);
      cluster_compound[size_t(i)] = &k;
      shape = k.shape.get();
      if (!c.anchored) inertia = k.inertia;
    } else if (!c.anchored) {
      shape->calculateLocalInertia(mass, inertia);
    }
    btRigidBody* body = cluster_body[size_t(i)] = add(mass, shape, inertia, to_bt(c.pose), i);
    if (!c.anchored) {
      body->setLinearVelocity(to_bt(c.velocity.linear));
      body->setAngularVelocity(to_bt(c.velocity.angular));
    }
  }
  for (int i = 0; i < movers; ++i) {
    const sim::Mover& m = b.movers[size_t(i)];
    btRigidBody* body = add(0, module_shape_, btVector3(0, 0, 0), to_bt(glide(m, to)), clusters + i);
    body->setCollisionFlags(body->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
    // Bullet takes a kinematic body's velocity from its last and its new pose.
    body->setInterpolationWorldTransform(to_bt(glide(m, to - 1)));
  }
  std::vector<btRigidBody*> prop_body;
  for (size_t i = 0; i < settings_.props.size(); ++i) {
    const PropSpec& p = settings_.props[i];
    btVector3 inertia(0, 0, 0);
    if (p.mass > 0) shapes_->props[i]->calculateLocalInertia(p.mass, inertia);
    btRigidBody* body =
        add(p.mass, shapes_->props[i].get(), inertia, to_bt(b.prop_poses[i]), clusters + movers + int(i));
    body->setLinearVelocity(to_bt(b.prop_velocities[i].linear));
    body->setAngularVelocity(to_bt(b.prop_velocities[i].angular));
    prop_body.push_back(body);
  }

  for (const Push& p : pushes) {
    const uint32_t c = b.cluster_of[p.module];
    if (c == sim::kNoCluster || b.clusters[c].anchored) continue;  // held by the ground, or gliding
    btRigidBody* body = cluster_body[c];
    body->applyImpulse(to_bt(p.impulse), to_bt(b.poses[p.module].position) - body->getWorldTransform().getOrigin());
  }

  world.stepSimulation(dt, 0, dt);

  for (int i = 0; i < clusters; ++i) {
    sim::Cluster& c = b.clusters[size_t(i)];
    if (c.anchored) continue;
    const btRigidBody& body = *cluster_body[size_t(i)];
    c.pose = from_bt(body.getWorldTransform());
    c.velocity = {from_bt(body.getLinearVelocity()), from_bt(body.getAngularVelocity())};
  }
  for (size_t i = 0; i < prop_body.size(); ++i) {
    if (settings_.props[i].mass <= 0) continue;
    b.prop_poses[i] = from_bt(prop_body[i]->getWorldTransform());
    b.prop_velocities[i] = {from_bt(prop_body[i]->getLinearVelocity()), from_bt(prop_body[i]->getAngularVelocity())};
  }

  // Contact forces per module from other bodies, from the impulses the solver applied. The ground
  // only carries what rests on it: its contacts do not count.
  force.assign(b.poses.size(), 0.0f);
  auto module_of = [&](const btCollisionObject* o, int child) -> int64_t {
    const int tag = o->getUserIndex();
    if (tag < 0 || tag >= clusters + movers) return -1;
    if (tag >= clusters) return b.movers[size_t(tag - clusters)].module;
    const sim::Cluster& c = b.clusters[size_t(tag)];
    if (c.count == 1) return b.members[c.first];
    // The compound holds only the surface members: its children are numbered among those.
    const std::vector<uint32_t>& member_of_child = cluster_compound[size_t(tag)]->member_of_child;
    if (child < 0 || size_t(child) >= member_of_child.size()) return -1;
    return b.members[c.first + member_of_child[size_t(child)]];
  };
  for (int i = 0; i < dispatcher.getNumManifolds(); ++i) {
    const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(i);
    for (int p = 0; p < manifold->getNumContacts(); ++p) {
      const btManifoldPoint& point = manifold->getContactPoint(p);
      const float f = point.getAppliedImpulse() / dt;
      if (f <= 0 || manifold->getBody0()->getUserIndex() < 0 || manifold->getBody1()->getUserIndex() < 0) continue;
      if (const int64_t m = module_of(manifold->getBody0(), point.m_index0); m >= 0) force[size_t(m)] += f;
      if (const int64_t m = module_of(manifold->getBody1(), point.m_index1); m >= 0) force[size_t(m)] += f;
    }
  }

  std::erase_if(shapes_->compounds, [&](const auto& entry) { return entry.second.used < to - 1; });
}

}  // namespace dw::physics
