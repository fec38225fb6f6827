#include "physics/dynamics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_set>

#include "physics/convert.h"
#include "physics/dynamics_parts.h"
#include "physics/islands.h"
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

Dynamics::Dynamics(const PhysicsSettings& settings, ModuleShape shape, float ground_z, uint32_t batch_bodies)
    : settings_(settings),
      batch_bodies_(std::max(batch_bodies, 1u)),
      shapes_(std::make_unique<Shapes>(shape, ground_z)),
      module_shape_(shapes_->module.get()),
      round_modules_(rolls(shape)) {
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

// How far a body can get over the step: its box, grown by what its speed, any pushes, gravity and
// turning can carry it (a turn moves no point further than the box's far corner from the
// centre). Anything that could touch it is then within the box.
ReachBox Dynamics::reach(const Body& body, float pushed, float turned, float* travel) const {
  btVector3 lo, hi;
  body.shape->getAabb(body.pose, lo, hi);
  const btVector3 o = body.pose.getOrigin();
  const btScalar radius = std::max((lo - o).length(), (hi - o).length());
  const float dt = settings_.dt;
  const float speed = to_bt(body.velocity.linear).length() + pushed;
  const float spin = to_bt(body.velocity.angular).length() + turned;
  // The slack covers Bullet's contact breaking threshold (0.02) and the contact threshold.
  const float moved = speed * dt + to_bt(settings_.gravity).length() * dt * dt + spin * dt * radius;
  if (travel != nullptr) *travel = moved;
  const float grow = moved + 0.1f + settings_.contact_threshold;
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

// Every body of the step, in tag order, and what each can reach over it.
void Dynamics::gather_bodies(Plan& plan, const sim::Bodies& b, std::span<const Push> pushes, int64_t to) {
  plan.compound_of.assign(b.clusters.size(), nullptr);
  plan.bodies.reserve(b.clusters.size() + b.movers.size() + settings_.props.size());
  for (int i = 0; i < plan.clusters; ++i) {
    const sim::Cluster& c = b.clusters[size_t(i)];
    Body body{.tag = i, .mass = c.anchored ? 0 : settings_.module_mass * float(c.count), .shape = module_shape_};
    if (c.count > 1) {
      const Compound& k = compound(b, c, to);
      plan.compound_of[size_t(i)] = &k;
      body.shape = k.shape.get();
      if (!c.anchored) body.inertia = k.inertia;
    } else if (!c.anchored) {
      body.shape->calculateLocalInertia(body.mass, body.inertia);
    }
    // An anchored cluster's frame is the world's: a lone member stands at its own pose (on the
    // first dynamics it stood at the origin, and what fell on where it was passed through it).
    body.pose = to_bt(c.anchored && c.count == 1 ? b.poses[b.members[c.first]] : c.pose);
    body.velocity = c.anchored ? sim::Velocity{} : c.velocity;
    plan.bodies.push_back(body);
  }
  for (int i = 0; i < plan.movers; ++i) {
    const sim::Mover& m = b.movers[size_t(i)];
    Body body{.tag = plan.clusters + i, .shape = module_shape_, .kinematic = true};
    body.pose = to_bt(glide(m, to));
    body.before = to_bt(glide(m, to - 1));
    plan.bodies.push_back(body);
  }
  for (size_t i = 0; i < settings_.props.size(); ++i) {
    const PropSpec& p = settings_.props[i];
    Body body{
        .tag = plan.clusters + plan.movers + int(i), .mass = std::max(p.mass, 0.0f), .shape = shapes_->props[i].get()};
    if (p.mass > 0) body.shape->calculateLocalInertia(p.mass, body.inertia);
    body.pose = to_bt(b.prop_poses[i]);
    body.velocity = b.prop_velocities[i];
    plan.bodies.push_back(body);
  }
  // Pushes speed a cluster up by at most |J| / m and turn it by at most |r| |J| / (least inertia).
  std::vector<Body>& bodies = plan.bodies;
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
    bodies[i].reach = reach(bodies[i], pushed[i], turned[i], &bodies[i].travel);
    if (bodies[i].kinematic) {  // from where it was to where it goes
      Body was = bodies[i];
      was.pose = was.before;
      bodies[i].reach.cover(reach(was, 0, 0));
      bodies[i].travel = (bodies[i].pose.getOrigin() - was.pose.getOrigin()).length();
    }
  }
}

// Islands among the bodies that move; each takes the fixed and kinematic bodies its box meets, and
// the pushes on its clusters (a cluster held by the ground, or a module gliding, takes none). An
// island sleeps when every body of it is a cluster that has slept or been still long enough
// (Cluster::still), none is pushed and nothing kinematic reaches it: whatever is awake and
// could touch a sleeping body wakes its whole island, as Bullet's islands wake.
void Dynamics::form_islands(Plan& plan, const sim::Bodies& b, std::span<const Push> pushes) const {
  const std::vector<Body>& bodies = plan.bodies;
  std::vector<uint32_t> moving;
  std::vector<ReachBox> boxes;
  for (uint32_t i = 0; i < bodies.size(); ++i)
    if (bodies[i].mass > 0) {
      moving.push_back(i);
      boxes.push_back(bodies[i].reach);
    }
  uint32_t count = 0;
  const std::vector<uint32_t> island_of = islands_of(boxes, count);
  plan.islands.assign(count, {});
  plan.asleep.assign(count, 1);
  std::vector<ReachBox> island_box(count);
  std::vector<uint8_t> boxed(count, 0);
  const int64_t sleep_steps = sleep_after_steps();
  for (size_t k = 0; k < moving.size(); ++k) {
    const uint32_t i = island_of[k];
    plan.islands[i].push_back(moving[k]);
    if (!boxed[i]) island_box[i] = boxes[k];
    island_box[i].cover(boxes[k]);
    boxed[i] = 1;
    const bool still =
        moving[k] < uint32_t(plan.clusters) && sleep_steps > 0 && b.clusters[moving[k]].still >= sleep_steps;
    if (!still) plan.asleep[i] = 0;
  }
  for (uint32_t j = 0; j < bodies.size(); ++j)
    if (bodies[j].mass <= 0)
      for (uint32_t i = 0; i < count; ++i)
        if (island_box[i].overlaps(bodies[j].reach)) {
          plan.islands[i].push_back(j);
          if (bodies[j].kinematic) plan.asleep[i] = 0;
        }
  for (std::vector<uint32_t>& island : plan.islands) std::sort(island.begin(), island.end());
  std::vector<uint32_t> island_of_body(bodies.size(), UINT32_MAX);
  for (size_t k = 0; k < moving.size(); ++k) island_of_body[moving[k]] = island_of[k];
  plan.pushes.assign(count, {});
  for (const Push& p : pushes) {
    const uint32_t c = b.cluster_of[p.module];
    if (c != sim::kNoCluster && !b.clusters[c].anchored && island_of_body[c] != UINT32_MAX) {
      plan.pushes[island_of_body[c]].push_back(&p);
      plan.asleep[island_of_body[c]] = 0;
    }
  }
  // Runs of consecutive islands holding at least batch_bodies_ bodies that move, each stepped in
  // one world: a world of its own for each of thousands of boxes in flight cost more than
  // stepping them. Like the islands, a function of the
  // state alone, never of the thread or rank count.
  plan.batches.clear();
  bool open = false;
  uint32_t held = 0;
  for (uint32_t i = 0; i < count; ++i) {
    if (!open) {
      plan.batches.push_back(i);
      open = true;
      held = 0;
    }
    if (!plan.asleep[i])
      held += uint32_t(std::count_if(plan.islands[i].begin(), plan.islands[i].end(),
                                     [&](uint32_t j) { return bodies[j].mass > 0; }));
    if (held >= batch_bodies_) open = false;
  }
  plan.batches.push_back(count);
}

int64_t Dynamics::sleep_after_steps() const {
  return settings_.sleep_after > 0 ? std::max<int64_t>(1, std::llround(settings_.sleep_after / settings_.dt)) : 0;
}

// Over ranks, what this rank's islands [first, last) wrote goes to every rank; each part is laid
// down as its islands wrote it, and the forces and contacts added up in island order (the ranks'
// runs are in island order), so each rank has the bits of one process.
void Dynamics::share(const Plan& plan, uint32_t first, uint32_t last, std::vector<IslandOutput>& outputs,
                     sim::Bodies& b, sim::RankExchange& ranks) {
  const int props_from = plan.clusters + plan.movers;
  std::vector<IslandResult> moved;
  std::vector<ContactForce> pushed_by;
  std::vector<sim::ContactPoint> touching;
  for (uint32_t i = first; i < last; ++i) {
    // A batch's output is its first island's, which may be one that sleeps: outputs are taken
    // from every island.
    for (uint32_t j : plan.islands[i])
      if (!plan.asleep[i] && plan.bodies[j].mass > 0) {
        const int tag = plan.bodies[j].tag;
        if (tag < plan.clusters) moved.push_back({tag, b.clusters[size_t(tag)].pose, b.clusters[size_t(tag)].velocity});
        else
          moved.push_back({tag, b.prop_poses[size_t(tag - props_from)], b.prop_velocities[size_t(tag - props_from)]});
      }
    for (const auto& [m, f] : outputs[i].forces) pushed_by.push_back({m, f});
    touching.insert(touching.end(), outputs[i].contacts.begin(), outputs[i].contacts.end());
  }
  std::vector<std::byte> mine;
  const uint64_t sizes[3] = {moved.size(), pushed_by.size(), touching.size()};
  sim::append_records<uint64_t>(mine, sizes);
  sim::append_records<IslandResult>(mine, moved);
  sim::append_records<ContactForce>(mine, pushed_by);
  sim::append_records<sim::ContactPoint>(mine, touching);
  // Every island's forces and contacts, from every rank, in island order: into the first output.
  outputs.assign(outputs.size(), {});
  IslandOutput& all = outputs.front();
  for (std::span<const std::byte> part : ranks.all_gather(mine)) {
    const std::span<const uint64_t> size = sim::records_of<uint64_t>(part.first(sizeof sizes));
    part = part.subspan(sizeof sizes);
    for (const IslandResult& r : sim::records_of<IslandResult>(part.first(size[0] * sizeof(IslandResult)))) {
      if (r.tag < plan.clusters) {
        b.clusters[size_t(r.tag)].pose = r.pose;
        b.clusters[size_t(r.tag)].velocity = r.velocity;
      } else {
        b.prop_poses[size_t(r.tag - props_from)] = r.pose;
        b.prop_velocities[size_t(r.tag - props_from)] = r.velocity;
      }
    }
    part = part.subspan(size[0] * sizeof(IslandResult));
    for (const ContactForce& f : sim::records_of<ContactForce>(part.first(size[1] * sizeof(ContactForce))))
      all.forces.emplace_back(f.module, f.value);
    const auto points = sim::records_of<sim::ContactPoint>(part.subspan(size[1] * sizeof(ContactForce)));
    all.contacts.insert(all.contacts.end(), points.begin(), points.end());
  }
}

// After the step: how long each cluster has been still (Bullet's deactivation rule: slower than
// the sleeping thresholds), a sleeping one kept still with no velocity; the contact cache from
// the islands stepped, and the sleeping islands' own kept as they were.
void Dynamics::settle(const Plan& plan, std::vector<IslandOutput>& outputs, sim::Bodies& b) {
  const int64_t sleep_steps = sleep_after_steps();
  std::vector<uint8_t> sleeping(b.clusters.size(), 0);
  for (size_t i = 0; i < plan.islands.size(); ++i)
    for (uint32_t j : plan.islands[i]) {
      if (j >= uint32_t(plan.clusters) || plan.bodies[j].mass <= 0) continue;
      sim::Cluster& c = b.clusters[j];
      if (plan.asleep[i]) {
        c.velocity = {};
        sleeping[j] = 1;
        continue;
      }
      // A cluster of an island woken this step starts counting again, as Bullet's activate() does.
      if (sleep_steps > 0 && c.still >= sleep_steps) c.still = 0;
      const bool slow = to_bt(c.velocity.linear).length2() < settings_.sleep_linear * settings_.sleep_linear &&
                        to_bt(c.velocity.angular).length2() < settings_.sleep_angular * settings_.sleep_angular;
      c.still = slow ? c.still + 1 : 0;
    }
  // The cache: the sleeping islands' points as they were, then each stepped island's. Each pair's
  // points come in runs (a manifold's, in the solver's order) and lie in one island: sorting the
  // runs by pair, stably, is the stable sort of the points by pair, at a run's cost, not a point's.
  struct Run {
    const sim::ContactPoint* first;  // its pair is first->a, first->b
    uint32_t count;
  };
  const auto asleep = [&](uint32_t side) {
    if (side >= b.cluster_of.size()) return false;  // the ground or a prop: never asleep
    const uint32_t c = b.cluster_of[side];
    return c != sim::kNoCluster && c < sleeping.size() && sleeping[c];
  };
  std::vector<Run> runs;
  size_t points = 0;
  const auto add_runs = [&](std::span<const sim::ContactPoint> from, bool kept_only_asleep) {
    for (const sim::ContactPoint& p : from) {
      if (kept_only_asleep && !asleep(p.a) && !asleep(p.b)) continue;
      if (!runs.empty() && runs.back().first + runs.back().count == &p && runs.back().first->a == p.a &&
          runs.back().first->b == p.b)
        ++runs.back().count;
      else runs.push_back({&p, 1});
      ++points;
    }
  };
  add_runs(b.contacts, true);
  for (const IslandOutput& out : outputs) add_runs(out.contacts, false);
  std::stable_sort(runs.begin(), runs.end(),
                   [](const Run& x, const Run& y) { return sim::contact_pair_less(*x.first, *y.first); });
  std::vector<sim::ContactPoint>& cache = spare_contacts_;
  cache.clear();
  cache.reserve(points);
  for (const Run& r : runs) cache.insert(cache.end(), r.first, r.first + r.count);
  b.contacts.swap(cache);
}

void Dynamics::step(sim::Bodies& b, std::span<const Push> pushes, int64_t to, std::vector<float>* force,
                    sim::WorkerPool& workers, sim::RankExchange* ranks) {
  Plan plan{.clusters = int(b.clusters.size()), .movers = int(b.movers.size())};
  gather_bodies(plan, b, pushes, to);
  form_islands(plan, b, pushes);
  const uint32_t count = uint32_t(plan.islands.size());
  islands_ = count;
  // Over ranks, this rank's run of the batches (weighed by the modules in them), as the islands
  // [first, last).
  const uint32_t batches = uint32_t(plan.batches.size()) - 1;
  uint32_t first_batch = 0, last_batch = batches;
  if (ranks != nullptr) {
    std::vector<uint64_t> weight(batches, 0);
    for (uint32_t k = 0; k < batches; ++k)
      for (uint32_t i = plan.batches[k]; i < plan.batches[k + 1]; ++i)
        for (uint32_t j : plan.islands[i]) weight[k] += j < uint32_t(plan.clusters) ? b.clusters[j].count : 1;
    const std::vector<uint32_t> runs = rank_runs(weight, uint32_t(ranks->ranks()));
    first_batch = runs[size_t(ranks->rank())];
    last_batch = runs[size_t(ranks->rank()) + 1];
  }
  const uint32_t first = plan.batches[first_batch], last = plan.batches[last_batch];
  stepped_.clear();
  for (uint32_t i = first; i < last; ++i)
    for (uint32_t j : plan.islands[i])
      if (!plan.asleep[i] && plan.bodies[j].mass > 0 && j < uint32_t(plan.clusters)) stepped_.push_back(j);
  std::sort(stepped_.begin(), stepped_.end());

  // Each worker steps a run of the batches; each writes only its own clusters and props, and its
  // forces and contacts into the output of its first island, added up in island order after.
  // The batches' bodies and the places of their worlds are found first, in order (the worlds'
  // map is not touched by the workers).
  std::vector<std::vector<uint32_t>> bodies(batches);
  std::vector<std::unique_ptr<BatchWorld>*> worlds(batches, nullptr);
  for (uint32_t k = first_batch; k < last_batch; ++k) {
    bodies[k] = awake_bodies(plan, plan.batches[k], plan.batches[k + 1]);
    if (!bodies[k].empty()) worlds[k] = &world_of(plan, bodies[k], k);
  }
  // The outputs a batch writes (its first island's) keep their memory from the last step; the
  // others give it back, so that what is kept is about one contact cache, however the batches
  // move between steps.
  std::vector<IslandOutput>& outputs = outputs_;
  outputs.resize(std::max<uint32_t>(count, 1));
  std::vector<uint8_t> written(outputs.size(), 0);
  for (uint32_t k = 0; k < batches; ++k) written[plan.batches[k]] = 1;
  for (size_t i = 0; i < outputs.size(); ++i) {
    outputs[i].forces.clear();
    if (written[i]) outputs[i].contacts.clear();
    else std::vector<sim::ContactPoint>().swap(outputs[i].contacts);
  }
  const unsigned runs = workers.size();
  while (shapes_->solvers.size() < runs)
    shapes_->solvers.push_back(std::make_unique<btSequentialImpulseConstraintSolver>());
  workers.run([&](unsigned run) {
    const uint32_t span = last_batch - first_batch;
    for (uint32_t k = first_batch + span * run / runs; k < first_batch + span * (run + 1) / runs; ++k)
      if (worlds[k] != nullptr)
        step_batch(plan, plan.batches[k], plan.batches[k + 1], bodies[k], *worlds[k], *shapes_->solvers[run], to, b,
                   force != nullptr, outputs[plan.batches[k]]);
  });
  // A world no batch stepped goes (its bodies may have gone to sleep, or into other batches).
  std::erase_if(shapes_->worlds, [&](const auto& entry) { return !entry.second || entry.second->used < to; });
  if (ranks != nullptr) share(plan, first, last, outputs, b, *ranks);

  if (force != nullptr) {
    force->assign(b.poses.size(), 0.0f);
    for (const IslandOutput& out : outputs)
      for (const auto& [m, f] : out.forces) (*force)[m] += f;
  }
  settle(plan, outputs, b);

  std::erase_if(shapes_->compounds, [&](const auto& entry) { return entry.second.used < to - 1; });
}

}  // namespace dw::physics
