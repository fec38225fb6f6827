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

#include "physics/box_plane.h"
#include "physics/convert.h"
#include "physics/islands.h"
#include "physics/shapes.h"
#include "physics/warm_start.h"

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
  // Per worker thread: Bullet's pools (not shared between threads), and a dispatcher, which a
  // world leaves empty (its pairs dropped first) and which takes a while to build.
  struct Worker {
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher{&config};
    BoxPlaneCreateFunc box_plane{false}, plane_box{true};
    Worker() {
      dispatcher.registerCollisionCreateFunc(BOX_SHAPE_PROXYTYPE, STATIC_PLANE_PROXYTYPE, &box_plane);
      dispatcher.registerCollisionCreateFunc(STATIC_PLANE_PROXYTYPE, BOX_SHAPE_PROXYTYPE, &plane_box);
      // A box on the ground gets all its corners in one query (physics/box_plane.h); other shapes
      // a few points a query, tilted, and the rest from the contact cache over steps
      // (physics/warm_start.h).
      config.setPlaneConvexMultipointIterations();
      config.setConvexConvexMultipointIterations();
    }
  };
  std::vector<std::unique_ptr<Worker>> workers;
  std::unique_ptr<btCollisionShape> module;
  btStaticPlaneShape ground;
  std::vector<std::unique_ptr<btCollisionShape>> props;
  std::unordered_map<uint64_t, Compound> compounds;  // by a hash of the local poses

  Shapes(ModuleShape shape, float ground_z) : module(make_module_shape(shape)), ground(btVector3(0, 0, 1), ground_z) {}
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
  const auto local = [&](uint32_t i) { return b.pose_in_cluster(b.members[i]); };
  for (uint32_t i = c.first; i < c.first + c.count; ++i) {
    const sim::Pose& p = local(i);
    for (float x : p.position) key = (key ^ std::bit_cast<uint32_t>(x)) * 0x100000001b3ull;
    for (float x : p.orientation) key = (key ^ std::bit_cast<uint32_t>(x)) * 0x100000001b3ull;
  }
  auto same = [&](const Compound& k) {
    if (k.local.size() != c.count) return false;
    for (uint32_t i = 0; i < c.count; ++i)
      if (!(k.local[i] == local(c.first + i))) return false;
    return true;
  };
  auto it = shapes_->compounds.find(key);
  while (it != shapes_->compounds.end() && !same(it->second)) it = shapes_->compounds.find(++key);
  if (it == shapes_->compounds.end()) {
    Compound k;
    btCompoundShape whole(true, static_cast<int>(c.count));
    for (uint32_t i = c.first; i < c.first + c.count; ++i) {
      k.local.push_back(local(i));
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

// One body of a step, in tag order: ground -1, then clusters, movers, props.
struct Dynamics::Body {
  int tag = 0;
  float mass = 0;
  btCollisionShape* shape = nullptr;
  btVector3 inertia{0, 0, 0};
  btTransform pose, before;  // before: a kinematic body's last pose (Bullet takes its velocity from the two)
  sim::Velocity velocity;
  bool kinematic = false;
  ReachBox reach;  // where it can be over the step
};

// How far a body can get over the step: its box, grown by what its speed, any pushes, gravity and
// turning can carry it (a turn moves no point further than the box's far corner from the
// centre). Anything that could touch it is then within the box.
ReachBox Dynamics::reach(const Body& body, float pushed, float turned) const {
  btVector3 lo, hi;
  body.shape->getAabb(body.pose, lo, hi);
  const btVector3 o = body.pose.getOrigin();
  const btScalar radius = std::max((lo - o).length(), (hi - o).length());
  const float dt = settings_.dt;
  const float speed = to_bt(body.velocity.linear).length() + pushed;
  const float spin = to_bt(body.velocity.angular).length() + turned;
  // The slack covers Bullet's contact breaking threshold (0.02) and the contact threshold.
  const float grow = speed * dt + to_bt(settings_.gravity).length() * dt * dt + spin * dt * radius + 0.1f +
                     settings_.contact_threshold;
  ReachBox box;
  for (int i = 0; i < 3; ++i) {
    box.lo[size_t(i)] = lo[i] - grow;
    box.hi[size_t(i)] = hi[i] + grow;
  }
  return box;
}

namespace {
// What an island wrote of one of its bodies that moves, and a contact force on a module: what
// ranks send each other of the islands they stepped.
struct IslandResult {
  int32_t tag;
  sim::Pose pose;
  sim::Velocity velocity;
};
struct ContactForce {
  sim::ModuleId module;
  float value;
};
}  // namespace

void Dynamics::step(sim::Bodies& b, std::span<const Push> pushes, int64_t to, std::vector<float>& force,
                    sim::WorkerPool& workers, sim::RankExchange* ranks) {
  const int clusters = static_cast<int>(b.clusters.size()), movers = static_cast<int>(b.movers.size());

  // Every body of the step, in tag order; which of them move (clusters not anchored, props with
  // mass), and what they can reach.
  std::vector<Body> bodies;
  std::vector<const Compound*> cluster_compound(b.clusters.size(), nullptr);
  for (int i = 0; i < clusters; ++i) {
    const sim::Cluster& c = b.clusters[size_t(i)];
    Body body{.tag = i, .mass = c.anchored ? 0 : settings_.module_mass * float(c.count), .shape = module_shape_};
    if (c.count > 1) {
      const Compound& k = compound(b, c, to);
      cluster_compound[size_t(i)] = &k;
      body.shape = k.shape.get();
      if (!c.anchored) body.inertia = k.inertia;
    } else if (!c.anchored) {
      body.shape->calculateLocalInertia(body.mass, body.inertia);
    }
    body.pose = to_bt(c.pose);
    body.velocity = c.anchored ? sim::Velocity{} : c.velocity;
    bodies.push_back(body);
  }
  for (int i = 0; i < movers; ++i) {
    const sim::Mover& m = b.movers[size_t(i)];
    Body body{.tag = clusters + i, .shape = module_shape_, .kinematic = true};
    body.pose = to_bt(glide(m, to));
    body.before = to_bt(glide(m, to - 1));
    bodies.push_back(body);
  }
  for (size_t i = 0; i < settings_.props.size(); ++i) {
    const PropSpec& p = settings_.props[i];
    Body body{.tag = clusters + movers + int(i), .mass = std::max(p.mass, 0.0f), .shape = shapes_->props[i].get()};
    if (p.mass > 0) body.shape->calculateLocalInertia(p.mass, body.inertia);
    body.pose = to_bt(b.prop_poses[i]);
    body.velocity = b.prop_velocities[i];
    bodies.push_back(body);
  }
  // Pushes speed a cluster up by at most |J| / m and turn it by at most |r| |J| / (least inertia).
  std::vector<float> pushed(bodies.size(), 0), turned(bodies.size(), 0);
  for (const Push& p : pushes) {
    const uint32_t c = b.cluster_of[p.module];
    if (c == sim::kNoCluster || b.clusters[c].anchored) continue;
    const Body& body = bodies[c];
    const float impulse = to_bt(p.impulse).length();
    const float arm = (to_bt(b.poses[p.module].position) - body.pose.getOrigin()).length();
    const float least = std::max(std::min({body.inertia.x(), body.inertia.y(), body.inertia.z()}), 1e-6f);
    pushed[c] += impulse / body.mass;
    turned[c] += arm * impulse / least;
  }
  for (size_t i = 0; i < bodies.size(); ++i) {
    bodies[i].reach = reach(bodies[i], pushed[i], turned[i]);
    if (bodies[i].kinematic) {  // from where it was to where it goes
      Body was = bodies[i];
      was.pose = was.before;
      bodies[i].reach.cover(reach(was, 0, 0));
    }
  }

  // Islands among the bodies that move; each takes the fixed and kinematic bodies its box meets.
  std::vector<uint32_t> moving;
  std::vector<ReachBox> boxes;
  for (uint32_t i = 0; i < bodies.size(); ++i)
    if (bodies[i].mass > 0) {
      moving.push_back(i);
      boxes.push_back(bodies[i].reach);
    }
  uint32_t count = 0;
  const std::vector<uint32_t> island_of = islands_of(boxes, count);
  std::vector<std::vector<uint32_t>> islands(count);
  std::vector<ReachBox> island_box(count);
  std::vector<uint8_t> boxed(count, 0);
  for (size_t k = 0; k < moving.size(); ++k) {
    const uint32_t i = island_of[k];
    islands[i].push_back(moving[k]);
    if (!boxed[i]) island_box[i] = boxes[k];
    island_box[i].cover(boxes[k]);
    boxed[i] = 1;
  }
  for (uint32_t j = 0; j < bodies.size(); ++j)
    if (bodies[j].mass <= 0)
      for (uint32_t i = 0; i < count; ++i)
        if (island_box[i].overlaps(bodies[j].reach)) islands[i].push_back(j);
  for (std::vector<uint32_t>& island : islands) std::sort(island.begin(), island.end());
  islands_ = count;
  // Each island's pushes, in their order: those on its clusters that move (a cluster held by the
  // ground, or a module gliding, takes none).
  std::vector<uint32_t> island_of_body(bodies.size(), UINT32_MAX);
  for (size_t k = 0; k < moving.size(); ++k) island_of_body[moving[k]] = island_of[k];
  std::vector<std::vector<const Push*>> island_pushes(count);
  for (const Push& p : pushes) {
    const uint32_t c = b.cluster_of[p.module];
    if (c != sim::kNoCluster && !b.clusters[c].anchored && island_of_body[c] != UINT32_MAX)
      island_pushes[island_of_body[c]].push_back(&p);
  }

  // Each worker steps a run of islands in worlds of its own (its own collision configuration:
  // Bullet's pools are not shared); each island writes only its own clusters and props, and its
  // contact forces into a list of its own, added up in island order after.
  while (shapes_->workers.size() < workers.size()) shapes_->workers.push_back(std::make_unique<Shapes::Worker>());
  std::vector<std::vector<std::pair<sim::ModuleId, float>>> forces(count);
  std::vector<std::vector<sim::ContactPoint>> kept(count);  // each island's contact points after the step
  const auto module_of = [&](const btCollisionObject* o, int child) -> int64_t {
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
  const auto side_of = [&](const btCollisionObject* o, int child) -> int64_t {
    const int tag = o->getUserIndex();
    if (tag < 0) return sim::kGroundContact;
    if (tag >= clusters + movers) return sim::contact_prop(uint32_t(tag - clusters - movers));
    return module_of(o, child);
  };
  const auto step_island = [&](uint32_t island, Shapes::Worker& worker) {
    const float dt = settings_.dt;
    btDbvtBroadphase broadphase;
    btCollisionDispatcher& dispatcher = worker.dispatcher;
    btDefaultCollisionConfiguration& config = worker.config;
    btSequentialImpulseConstraintSolver solver;
    std::vector<std::unique_ptr<btRigidBody>> rigid;  // outlive the world, which unlinks them when it goes
    WarmStartedWorld world(&dispatcher, &broadphase, &solver, &config, b.contacts, side_of);
    const PairsDroppedFirst<btDiscreteDynamicsWorld> teardown{world};
    world.setGravity(to_bt(settings_.gravity));
    world.getSolverInfo().m_numIterations = settings_.solver_iterations;
    world.getDispatchInfo().m_deterministicOverlappingPairs = true;
    const auto add = [&](float mass, btCollisionShape* shape, const btVector3& inertia, const btTransform& pose,
                         int tag) {
      btRigidBody::btRigidBodyConstructionInfo info(mass, nullptr, shape, inertia);
      info.m_startWorldTransform = pose;
      info.m_friction = settings_.friction;
      info.m_restitution = settings_.restitution;
      auto& body = rigid.emplace_back(std::make_unique<btRigidBody>(info));
      body->setActivationState(DISABLE_DEACTIVATION);  // sleeping changes contacts (docs/design.md §8)
      body->setUserIndex(tag);
      world.addRigidBody(body.get());
      return body.get();
    };
    btTransform identity;
    identity.setIdentity();
    add(0, &shapes_->ground, btVector3(0, 0, 0), identity, -1);
    std::vector<std::pair<int, btRigidBody*>> mine;  // (tag, body) of the bodies that move
    for (uint32_t i : islands[island]) {
      const Body& body = bodies[i];
      btRigidBody* r = add(body.mass, body.shape, body.inertia, body.pose, body.tag);
      if (body.kinematic) {
        r->setCollisionFlags(r->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
        r->setInterpolationWorldTransform(body.before);
      } else if (body.mass > 0) {
        r->setLinearVelocity(to_bt(body.velocity.linear));
        r->setAngularVelocity(to_bt(body.velocity.angular));
        mine.emplace_back(body.tag, r);
      }
    }
    for (const Push* p : island_pushes[island]) {  // `mine` is in tag order, a cluster's tag its index
      const int c = int(b.cluster_of[p->module]);
      btRigidBody* body =
          std::lower_bound(mine.begin(), mine.end(), c, [](const auto& x, int tag) { return x.first < tag; })->second;
      body->applyImpulse(to_bt(p->impulse), to_bt(b.poses[p->module].position) - body->getWorldTransform().getOrigin());
    }

    world.stepSimulation(dt, 0, dt);
    world.keep_contacts(kept[island]);

    for (const auto& [tag, body] : mine) {
      const sim::Pose pose = from_bt(body->getWorldTransform());
      const sim::Velocity velocity{from_bt(body->getLinearVelocity()), from_bt(body->getAngularVelocity())};
      if (tag < clusters) {
        b.clusters[size_t(tag)].pose = pose;
        b.clusters[size_t(tag)].velocity = velocity;
      } else {
        b.prop_poses[size_t(tag - clusters - movers)] = pose;
        b.prop_velocities[size_t(tag - clusters - movers)] = velocity;
      }
    }
    // Contact forces per module from other bodies, from the impulses the solver applied. The
    // ground only carries what rests on it: its contacts do not count.
    for (int i = 0; i < dispatcher.getNumManifolds(); ++i) {
      const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(i);
      for (int p = 0; p < manifold->getNumContacts(); ++p) {
        const btManifoldPoint& point = manifold->getContactPoint(p);
        const float f = point.getAppliedImpulse() / dt;
        if (f <= 0 || manifold->getBody0()->getUserIndex() < 0 || manifold->getBody1()->getUserIndex() < 0) continue;
        if (const int64_t m = module_of(manifold->getBody0(), point.m_index0); m >= 0)
          forces[island].emplace_back(sim::ModuleId(m), f);
        if (const int64_t m = module_of(manifold->getBody1(), point.m_index1); m >= 0)
          forces[island].emplace_back(sim::ModuleId(m), f);
      }
    }
  };
  // Over ranks, this rank's run of the islands (weighed by the modules in them).
  uint32_t first = 0, last = count;
  if (ranks != nullptr) {
    std::vector<uint64_t> weight(count, 0);
    for (uint32_t i = 0; i < count; ++i)
      for (uint32_t j : islands[i]) weight[i] += j < uint32_t(clusters) ? b.clusters[j].count : 1;
    const std::vector<uint32_t> runs = rank_runs(weight, uint32_t(ranks->ranks()));
    first = runs[size_t(ranks->rank())];
    last = runs[size_t(ranks->rank()) + 1];
  }
  stepped_.clear();
  for (uint32_t i = first; i < last; ++i)
    for (uint32_t j : islands[i])
      if (bodies[j].mass > 0 && j < uint32_t(clusters)) stepped_.push_back(j);
  std::sort(stepped_.begin(), stepped_.end());
  const unsigned runs = workers.size();
  workers.run([&](unsigned run) {
    for (uint32_t i = first + (last - first) * run / runs; i < first + (last - first) * (run + 1) / runs; ++i)
      step_island(i, *shapes_->workers[run]);
  });

  force.assign(b.poses.size(), 0.0f);
  std::vector<sim::ContactPoint> cache;  // the next step's warm start, in island order, then by pair
  if (ranks == nullptr) {
    for (const auto& list : forces)
      for (const auto& [m, f] : list) force[m] += f;
    for (const auto& list : kept) cache.insert(cache.end(), list.begin(), list.end());
  } else {
    // What this rank's islands wrote, to every rank; each part is laid down as its islands wrote
    // it, and the forces added up in island order (the ranks' runs are in island order), so each
    // rank has the bits of one process.
    std::vector<IslandResult> moved;
    std::vector<ContactForce> pushed_by;
    std::vector<sim::ContactPoint> touching;
    for (uint32_t i = first; i < last; ++i) {
      for (uint32_t j : islands[i])
        if (bodies[j].mass > 0) {
          const int tag = bodies[j].tag;
          if (tag < clusters) moved.push_back({tag, b.clusters[size_t(tag)].pose, b.clusters[size_t(tag)].velocity});
          else
            moved.push_back({tag, b.prop_poses[size_t(tag - clusters - movers)],
                             b.prop_velocities[size_t(tag - clusters - movers)]});
        }
      for (const auto& [m, f] : forces[i]) pushed_by.push_back({m, f});
      touching.insert(touching.end(), kept[i].begin(), kept[i].end());
    }
    std::vector<std::byte> mine;
    const uint64_t sizes[3] = {moved.size(), pushed_by.size(), touching.size()};
    sim::append_records<uint64_t>(mine, sizes);
    sim::append_records<IslandResult>(mine, moved);
    sim::append_records<ContactForce>(mine, pushed_by);
    sim::append_records<sim::ContactPoint>(mine, touching);
    for (std::span<const std::byte> part : ranks->all_gather(mine)) {
      const std::span<const uint64_t> size = sim::records_of<uint64_t>(part.first(sizeof sizes));
      part = part.subspan(sizeof sizes);
      for (const IslandResult& r : sim::records_of<IslandResult>(part.first(size[0] * sizeof(IslandResult)))) {
        if (r.tag < clusters) {
          b.clusters[size_t(r.tag)].pose = r.pose;
          b.clusters[size_t(r.tag)].velocity = r.velocity;
        } else {
          b.prop_poses[size_t(r.tag - clusters - movers)] = r.pose;
          b.prop_velocities[size_t(r.tag - clusters - movers)] = r.velocity;
        }
      }
      part = part.subspan(size[0] * sizeof(IslandResult));
      for (const ContactForce& f : sim::records_of<ContactForce>(part.first(size[1] * sizeof(ContactForce))))
        force[f.module] += f.value;
      const auto points = sim::records_of<sim::ContactPoint>(part.subspan(size[1] * sizeof(ContactForce)));
      cache.insert(cache.end(), points.begin(), points.end());
    }
  }
  // Each pair's points lie in one island, in the solver's order: sorting by pair keeps that order.
  std::stable_sort(cache.begin(), cache.end(), sim::contact_pair_less);
  b.contacts = std::move(cache);

  std::erase_if(shapes_->compounds, [&](const auto& entry) { return entry.second.used < to - 1; });
}

}  // namespace dw::physics
