#include "physics/bullet_world.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "physics/clusters.h"
#include "physics/pivot.h"
#include "sim/host_program.h"

namespace dw::physics {
namespace {

float lowest_bottom(const sim::Lattice& lattice) {
  float z = 0;
  bool any = false;
  for (sim::ModuleId m = 0; m < lattice.occupied.size(); ++m)
    if (lattice.occupied[m]) {
      z = any ? std::min(z, lattice.position(m)[2]) : lattice.position(m)[2];
      any = true;
    }
  return z - 0.5f;
}

float distance(const sim::Vec3& a, const sim::Vec3& b) { return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]); }

std::string who(const sim::Actuation& a, int64_t step) {
  return "module " + std::to_string(a.module) + " at step " + std::to_string(step);
}

// Every rank's `mine`, in rank order (a collective call over ranks); in one process, `mine`.
template <class T>
std::vector<T> from_every_rank(sim::RankExchange* ranks, std::vector<T> mine) {
  if (!ranks) return mine;
  std::vector<T> all;
  sim::all_gather_into<T>(*ranks, mine, all);
  return all;
}

}  // namespace

BulletWorld::BulletWorld(PhysicsSettings settings, const sim::Lattice& lattice)
    : settings_(std::move(settings)),
      shape_(settings_.shape.value_or(default_shape(lattice.spec.kind))),
      ground_z_(lowest_bottom(lattice)),
      dynamics_(settings_, shape_, ground_z_),
      contacts_(shape_, settings_.contact_threshold) {}

bool BulletWorld::touches_ground(const sim::Pose& pose) const {
  return pose.position[2] - 0.5f - ground_z_ <= settings_.contact_threshold;
}

void BulletWorld::initialize(const sim::Model& model, sim::State& state, sim::WorkerPool& workers) {
  const uint32_t n = model.module_count();
  state.present = model.lattice.occupied;
  sim::Bodies& b = state.bodies;
  b = sim::Bodies{};
  b.poses = decltype(b.poses)(sim::CellPose{model.lattice.spec, 1});  // every module at its cell
  b.poses.resize(n);
  b.velocities.resize(n);
  b.local.resize(n);
  for (const PropSpec& p : settings_.props) {
    b.prop_poses.push_back(p.pose);
    b.prop_velocities.push_back(p.velocity);
  }
  contacts_.reset();
  // Over ranks, this rank's window of the graph (ContactGraph::update): no rank holds it whole.
  state.graph = contacts_.update(b, state.present, workers, nullptr, ranks_, &owners_);
  // Real modules latch to what they touch as they are put in place, and to the ground. Each rank
  // sets its own modules' bonds to larger ids (all of them in one process), and the ranks swap
  // the bytes that differ from the lattice's default and the bonds listed: a latched lattice's
  // three million bonds are not gathered.
  b.bonds = sim::BondSet(model.lattice.spec, settings_.bonds, n);
  const uint32_t me = ranks_ ? static_cast<uint32_t>(ranks_->rank()) : 0;
  struct Links {
    sim::ModuleId module;
    uint32_t bits;
  };
  std::vector<Links> differing;
  std::vector<sim::Bond> listed;
  for (sim::ModuleId m = 0; m < n; ++m) {
    if (ranks_ && owners_.rank_of(m) != me) continue;
    uint32_t bits = 0;
    if (state.present[m]) {
      if (settings_.bonds)
        for (sim::ModuleId o : state.graph->neighbors(m))
          if (o > m) {
            if (const uint8_t bit = b.bonds.bit({m, o})) bits |= bit;
            else listed.push_back({m, o});
          }
      if (settings_.anchor && touches_ground(b.poses[m])) bits |= sim::kGroundBit;
    }
    if (bits != b.bonds.default_links(m)) differing.push_back({m, bits});
  }
  for (const Links& x : from_every_rank(ranks_, std::move(differing)))
    b.bonds.set_links(x.module, static_cast<uint8_t>(x.bits));
  listed = from_every_rank(ranks_, std::move(listed));
  std::sort(listed.begin(), listed.end());
  b.bonds.insert(listed);
  regroup_all(state);
  // Members of a cluster are measured at their poses in it: the graph of step 0 is the one a
  // restored world finds (and the first step does not pay for measuring every pair again). Only
  // the members of clusters that move have a frame; nothing else changed since the first update.
  std::vector<sim::ModuleId> framed;
  for (const sim::Cluster& c : b.clusters)
    if (!c.anchored && c.count > 1)
      framed.insert(framed.end(), b.members.begin() + c.first, b.members.begin() + c.first + c.count);
  state.graph = contacts_.update(b, state.present, workers, &framed, ranks_, &owners_);
  contacts_known_ = true;
}

void BulletWorld::restore(const sim::Model&, const sim::State&) {
  // What Bullet keeps from a step computes the next as if made afresh (physics/dynamics.h), and
  // the contact graph measures
  // again whatever differs from what it measured last, whichever state that was. The bonds are
  // indexed again when next needed.
  bond_index_.invalidate();
  changes_.clear();
  contacts_known_ = false;
}

// Forms the clusters from all the bonds (when what changed is not known, or rarely changes).
void BulletWorld::regroup_all(sim::State& state) {
  form_clusters(state.bodies, state.present, dynamics_.module_shape());
  bond_index_.invalidate();
  changes_.clear();
  contacts_known_ = false;  // any frame may have changed
}

// Regroups the clusters after the changes since they were formed, looking only at those.
void BulletWorld::regroup(sim::State& state) {
  if (changes_.empty()) return;
  changes_.normalize();
  if (!bond_index_.valid()) bond_index_.rebuild(state.bodies.bonds);
  regrouper_(state.bodies, state.present, changes_, bond_index_, dynamics_.module_shape());
  changes_.clear();
  changed_.insert(changed_.end(), regrouper_.reframed().begin(), regrouper_.reframed().end());
}

void BulletWorld::remove_module(const sim::Model& model, sim::State& state, sim::ModuleId m) {
  if (!state.present[m]) return;
  World::remove_module(model, state, m);
  // Its body goes with it: no bonds, no glide, no cluster; the rest regroup without it.
  sim::Bodies& b = state.bodies;
  b.bonds.erase(bonds_of(b.bonds, std::span(&m, 1)));
  std::erase_if(b.movers, [&](const sim::Mover& x) { return x.module == m; });
  b.velocities.set(m, {});
  regroup_all(state);
  graph_stale_ = true;  // the clusters it left may have new frames
}

// Carries out one request; returns whether the bonds changed.
bool BulletWorld::carry_out(const sim::Actuation& a, sim::State& state, std::vector<Push>& pushes,
                            std::vector<sim::ModuleId>& leaving) {
  sim::Bodies& b = state.bodies;
  const int64_t asked = state.step - 1;
  // Requests to release or make a bond change the bonds (and their index) at once: a later request
  // of the same step sees them.
  const auto release = [&](std::span<const sim::Bond> gone) {
    if (gone.empty()) return false;
    b.bonds.erase(gone);
    if (bond_index_.valid()) bond_index_.apply(b.bonds, gone, {});
    changes_.removed.insert(changes_.removed.end(), gone.begin(), gone.end());
    return true;
  };
  switch (a.kind) {
    case sim::Actuation::Kind::Push: pushes.push_back({a.module, a.vector}); return false;
    case sim::Actuation::Kind::Release: {
      const sim::Bond bond{std::min(a.module, a.other), std::max(a.module, a.other)};
      return b.bonds.contains(bond) && release(std::span(&bond, 1));
    }
    case sim::Actuation::Kind::ReleaseAll: return release(bonds_of(b.bonds, std::span(&a.module, 1)));
    case sim::Actuation::Kind::Bond: {
      if (b.moving(a.module) || b.moving(a.other)) return false;  // latches only what is still
      const sim::Bond bond{std::min(a.module, a.other), std::max(a.module, a.other)};
      if (!b.bonds.insert(bond)) return false;
      if (bond_index_.valid()) bond_index_.apply(b.bonds, {}, std::span(&bond, 1));
      changes_.added.push_back(bond);
      return true;
    }
    case sim::Actuation::Kind::Move: {
      const float length = std::hypot(a.vector[0], a.vector[1], a.vector[2]);
      if (std::abs(length - 1) > 1e-3f)
        throw sim::ProgramError("a lattice move of " + who(a, asked) + " is " + std::to_string(length) +
                                " module sizes long; a move goes to an adjacent cell, one size away");
      if (b.moving(a.module)) return false;
      sim::Pose to = b.poses[a.module];
      for (int i = 0; i < 3; ++i) to.position[i] += a.vector[i];
      if (taken_by(a.module, to.position, state)) return false;
      set_off({a.module, b.poses[a.module], to, asked, settings_.move_steps}, state, leaving);
      return true;  // it leaves its cluster
    }
    case sim::Actuation::Kind::Pivot: {
      if (b.moving(a.module)) return false;
      const auto offset = [&] {
        std::ostringstream text;
        text << "(" << a.vector[0] << ", " << a.vector[1] << ", " << a.vector[2] << ")";
        return text.str();
      };
      const auto refuse = [&](const std::string& why) {
        throw sim::ProgramError("a pivot of " + who(a, asked) + " about module " + std::to_string(a.other) +
                                " to the cell at " + offset() + " from it: " + why);
      };
      if (a.other >= b.poses.size() || !state.present[a.other]) refuse("there is no such module");
      if (b.moving(a.other)) refuse("that module is moving");
      const auto planned = pivot_arcs(shape_, b.poses[a.module].position, b.poses[a.other].position, a.vector);
      if (const auto* why = std::get_if<std::string>(&planned)) refuse(*why);
      sim::Vec3 cell = b.poses[a.module].position;
      for (int i = 0; i < 3; ++i) cell[i] += a.vector[i];
      if (const auto m = taken_by(a.module, cell, state)) refuse("the cell is taken by module " + std::to_string(*m));
      if (b.poses.defaults().lattice.kind == sim::LatticeKind::Hex2dVertical) {
        // Against gravity: it must arrive supported by the still modules around the cell.
        std::vector<Holder> touching;
        for (sim::ModuleId o : contacts_.near(cell, 1.05f))
          if (o != a.module && !b.moving(o) && distance(b.poses[o].position, cell) < 1.05f)
            touching.push_back({o, b.poses[o].position});
        if (const auto why = unsupported_in_vertical_plane(cell, ground_z_, touching)) refuse(*why);
      }
      // The sweep: the body at 16 points of its turn must not pass into another module (touching
      // is fine: a rolling cube keeps the edge it turns about). The first clear arc is taken.
      constexpr int kSamples = 16;
      constexpr float kOverlap = 0.02f;
      std::optional<sim::ModuleId> blocked;
      for (const PivotArc& arc : std::get<std::vector<PivotArc>>(planned)) {
        sim::Mover mover{a.module,  b.poses[a.module], {},        asked,    settings_.move_steps,
                         arc.pivot, arc.axis,          arc.angle, arc.spin, a.other};  // turns on a.other
        mover.to = turn(mover, 1);
        mover.to.position = cell;  // exactly the cell
        std::optional<sim::ModuleId> in_the_way;
        for (int k = 1; k < kSamples && !in_the_way; ++k) {
          const sim::Pose at = turn(mover, float(k) / kSamples);
          for (sim::ModuleId o : contacts_.near(at.position, contacts_.reach()))
            if (o != a.module && o != a.other && contacts_.distance(at, b.poses[o]) < -kOverlap) {
              in_the_way = o;
              break;
            }
        }
        if (!in_the_way) {
          set_off(mover, state, leaving);
          return true;
        }
        if (!blocked) blocked = in_the_way;
      }
      refuse("its sweep passes through module " + std::to_string(*blocked));
      return false;
    }
  }
  return false;
}

// The module other than `self` in the cell centred at `at`, but one gliding out of it, or one
// gliding into it.
std::optional<sim::ModuleId> BulletWorld::taken_by(sim::ModuleId self, const sim::Vec3& at,
                                                   const sim::State& state) const {
  const sim::Bodies& b = state.bodies;
  for (sim::ModuleId m : contacts_.near(at, 0.5f))
    if (m != self && !b.moving(m)) return m;
  // Among the movers whose targets lie within half a size along x, the first in module order.
  std::optional<sim::ModuleId> found;
  for (auto it = std::lower_bound(heading_.begin(), heading_.end(), std::pair{at[0] - 0.5f, sim::ModuleId{0}});
       it != heading_.end() && it->first < at[0] + 0.5f; ++it) {
    const sim::Mover* mover = std::lower_bound(b.movers.data(), b.movers.data() + b.movers.size(), it->second,
                                               [](const sim::Mover& x, sim::ModuleId id) { return x.module < id; });
    if (distance(mover->to.position, at) < 0.5f && (!found || it->second < *found)) found = it->second;
  }
  return found;
}

// A lattice move or a pivot sets off: the module leaves its cluster, and its bonds go after every
// request is carried out, in one pass over the bonds (a bond made to it meanwhile is refused, as
// it is moving, so the result is the same).
void BulletWorld::set_off(const sim::Mover& mover, sim::State& state, std::vector<sim::ModuleId>& leaving) {
  sim::Bodies& b = state.bodies;
  b.movers.insert(std::lower_bound(b.movers.begin(), b.movers.end(), mover,
                                   [](const sim::Mover& x, const sim::Mover& y) { return x.module < y.module; }),
                  mover);
  b.velocities.set(mover.module, {});
  const std::pair target{mover.to.position[0], mover.module};
  heading_.insert(std::lower_bound(heading_.begin(), heading_.end(), target), target);
  leaving.push_back(mover.module);
  changes_.stopped.push_back(mover.module);
}

// The bonds of `modules` (to others and to the ground), sorted, found by the index of bonds.
std::vector<sim::Bond> BulletWorld::bonds_of(const sim::BondSet& bonds, std::span<const sim::ModuleId> modules) {
  if (!bond_index_.valid()) bond_index_.rebuild(bonds);
  std::vector<sim::Bond> found;
  for (sim::ModuleId m : modules) bond_index_.bonds_of(bonds, m, [&](const sim::Bond& x) { found.push_back(x); });
  std::sort(found.begin(), found.end());
  found.erase(std::unique(found.begin(), found.end()), found.end());
  return found;
}

// The bonds of the modules setting off go, in one pass.
void BulletWorld::let_go(std::span<const sim::ModuleId> leaving, sim::State& state) {
  sim::Bodies& b = state.bodies;
  if (leaving.empty()) return;
  const std::vector<sim::Bond> gone = bonds_of(b.bonds, leaving);
  if (gone.empty()) return;
  b.bonds.erase(gone);
  bond_index_.apply(b.bonds, gone, {});
  changes_.removed.insert(changes_.removed.end(), gone.begin(), gone.end());
}

std::vector<sim::Bond> BulletWorld::touching_bonds(const sim::State& state, std::span<const sim::ModuleId> modules) {
  std::vector<sim::Bond> found;
  const uint32_t me = ranks_ ? static_cast<uint32_t>(ranks_->rank()) : 0;
  for (sim::ModuleId m : modules)
    if (state.present[m] && (!ranks_ || owners_.rank_of(m) == me))
      for (sim::ModuleId o : state.graph->neighbors(m))
        if (!state.bodies.moving(o)) found.push_back({std::min(m, o), std::max(m, o)});
  return from_every_rank(ranks_, std::move(found));
}

// Modules ending a lattice move latch to what they touch (and the ground).
void BulletWorld::latch(std::span<const sim::ModuleId> arrived, sim::State& state) {
  sim::Bodies& b = state.bodies;
  std::vector<sim::Bond> made;
  if (settings_.bonds) made = touching_bonds(state, arrived);
  if (settings_.anchor)
    for (sim::ModuleId m : arrived)
      if (touches_ground(b.poses[m])) made.push_back({m, sim::kGround});
  std::sort(made.begin(), made.end());
  made.erase(std::unique(made.begin(), made.end()), made.end());
  b.bonds.insert(made);
  if (bond_index_.valid()) bond_index_.apply(b.bonds, {}, made);
  changes_.added.insert(changes_.added.end(), made.begin(), made.end());
  changes_.started.insert(changes_.started.end(), arrived.begin(), arrived.end());
}

// Steps the bodies; a module pushed harder than the break force loses its bonds, and the step is
// done again from the same start without them (bounded: each round breaks at least one bond). A
// dynamics step changes only the clusters' frames, the props and the contact cache, so only those are
// kept to redo it.
void BulletWorld::step_bodies(sim::State& state, std::span<const Push> pushes, sim::WorkerPool& workers) {
  sim::Bodies& b = state.bodies;
  if (dynamics_.idle(b)) {
    b.contacts.clear();  // nothing moves: nothing to warm-start
    return;
  }
  // Only a module with a bond can be pushed off it: without one, no contact force is gathered and
  // nothing is kept to redo the step with (a 20^3 pile's contact cache is 8 MB).
  if (settings_.break_force <= 0 || b.bonds.empty()) {
    dynamics_.step(b, pushes, state.step, nullptr, workers, ranks_);
    place_members(b);
    return;
  }
  std::vector<sim::Cluster> clusters = b.clusters;
  const std::vector<sim::Pose> prop_poses = b.prop_poses;
  const std::vector<sim::Velocity> prop_velocities = b.prop_velocities;
  const std::vector<sim::ContactPoint> contacts = b.contacts;
  for (int round = 0;; ++round) {
    dynamics_.step(b, pushes, state.step, &force_, workers, ranks_);
    if (round == 8) break;
    // Every bond of a module pushed too hard (its bond to the ground too) breaks.
    std::vector<sim::ModuleId> pushed;
    for (sim::ModuleId m = 0; m < force_.size(); ++m)
      if (force_[m] > settings_.break_force) pushed.push_back(m);
    const std::vector<sim::Bond> broken = bonds_of(b.bonds, pushed);
    if (broken.empty()) break;
    b.bonds.erase(broken);
    b.clusters = clusters;
    b.prop_poses = prop_poses;
    b.prop_velocities = prop_velocities;
    b.contacts = contacts;
    regroup_all(state);
    clusters = b.clusters;
  }
  place_members(b);
}

void BulletWorld::advance(const sim::Model&, sim::State& state, std::span<const sim::Actuation> actuations,
                          sim::WorkerPool& workers) {
  sim::Bodies& b = state.bodies;
  std::vector<Push> pushes;
  bool changed = false;
  // Moves and pivots look for modules in the grid of module centres (which a restored state may
  // not match yet); requests change no pose.
  if (!contacts_known_ && std::any_of(actuations.begin(), actuations.end(), [](const sim::Actuation& a) {
        return a.kind == sim::Actuation::Kind::Move || a.kind == sim::Actuation::Kind::Pivot;
      }))
    contacts_.place(b, state.present);
  // Where the movers are heading, by x: what taken_by looks at (a thousand moves among a thousand
  // movers are not a million comparisons).
  heading_.clear();
  if (!actuations.empty()) {
    for (const sim::Mover& m : b.movers) heading_.emplace_back(m.to.position[0], m.module);
    std::sort(heading_.begin(), heading_.end());
  }
  std::vector<sim::ModuleId> leaving;  // modules setting off on a lattice move
  for (const sim::Actuation& a : actuations) changed |= carry_out(a, state, pushes, leaving);
  let_go(leaving, state);
  if (changed) regroup(state);
  // Nothing moves and no frame changes: the graph stays (a resting lattice costs no physics).
  const bool still = !changed && !graph_stale_ && b.movers.empty() && dynamics_.idle(b);

  step_bodies(state, pushes, workers);
  // What moved: the clusters Bullet moves and the modules gliding.
  for (const sim::Cluster& c : b.clusters)
    if (!c.anchored)
      changed_.insert(changed_.end(), b.members.begin() + c.first, b.members.begin() + c.first + c.count);
  for (const sim::Mover& m : b.movers) changed_.push_back(m.module);

  // Lattice moves go on; those that arrive latch to what they touch once the graph is read.
  std::vector<sim::ModuleId> arrived;
  for (const sim::Mover& m : b.movers) {
    b.poses.set(m.module, glide(m, state.step));
    if (state.step - m.start >= m.steps) {
      arrived.push_back(m.module);
      b.velocities.set(m.module, {});
    } else {
      const float per_second = 1 / (float(m.steps) * settings_.dt);
      sim::Velocity v = b.velocities[m.module];
      for (int i = 0; i < 3; ++i) v.linear[i] = (m.to.position[i] - m.from.position[i]) * per_second;
      b.velocities.set(m.module, v);
    }
  }
  std::erase_if(b.movers, [&](const sim::Mover& m) { return state.step - m.start >= m.steps; });

  // A restored state is compared in full once: the graph's memory is of another state.
  if (!still) {
    state.graph = contacts_.update(b, state.present, workers, contacts_known_ ? &changed_ : nullptr, ranks_, &owners_);
    contacts_known_ = true;
  }
  if (check_) {
    const auto full = check_->update(b, state.present, workers);
    for (sim::ModuleId m = 0; m < full->module_count(); ++m) {
      const auto whole = full->neighbors(m), read = state.graph->neighbors(m);
      if (state.graph->holds(m) ? !std::ranges::equal(whole, read) : !read.empty())
        throw std::logic_error("the contact graph read by what changed differs from the full one at step " +
                               std::to_string(state.step) + " (module " + std::to_string(m) + "'s neighbours)");
    }
  }
  graph_stale_ = false;
  changed_.clear();

  if (!arrived.empty()) {
    latch(arrived, state);
    regroup(state);
  }
}

}  // namespace dw::physics
