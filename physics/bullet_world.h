// The physical World (docs/design.md §8): every module a Bullet rigid body on a ground, latched to the
// modules it touches; the neighbour graph read from contacts after every step; programs push
// their modules, make lattice moves, and release or make bonds.
//
// A step: the programs' requests are carried out (in module order), the bodies that can move are
// stepped (physics/dynamics.h), a module pushed by contacts harder than the break force loses its
// bonds and the step is done again without them, lattice moves go on, the graph is read from
// contacts, and a module that ends a lattice move latches to what it touches.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "physics/contact_graph.h"
#include "physics/dynamics.h"
#include "physics/regroup.h"
#include "physics/settings.h"
#include "sim/world.h"

namespace dw::physics {

class BulletWorld final : public sim::World {
 public:
  // The lattice fixes the module shape when the settings leave it open.
  BulletWorld(PhysicsSettings settings, const sim::Lattice& lattice);

  void initialize(const sim::Model& model, sim::State& state, sim::WorkerPool& workers) override;
  void restore(const sim::Model& model, const sim::State& state) override;
  void advance(const sim::Model& model, sim::State& state, std::span<const sim::Actuation> actuations,
               sim::WorkerPool& workers) override;
  void remove_module(const sim::Model& model, sim::State& state, sim::ModuleId m) override;
  bool moves() const override { return true; }
  // Over ranks, each steps a run of the islands (Dynamics::step) and holds the neighbour graph of
  // its window, measured by itself (ContactGraph::update); bonds are made by the owners of the
  // modules that latch.
  void share_over(sim::RankExchange* ranks, const sim::ModuleOwners& owners) override {
    ranks_ = ranks;
    owners_ = owners;
  }

  // Checks every contact graph read by what changed against one read by comparing every module
  // (a second ContactGraph measuring alongside): a difference throws std::logic_error naming the
  // step. For tests: what the world says changed must be all that changed.
  void check_contacts() { check_ = std::make_unique<ContactGraph>(shape_, settings_.contact_threshold); }

  const PhysicsSettings& settings() const { return settings_; }
  ModuleShape shape() const { return shape_; }
  float ground_z() const { return ground_z_; }

 private:
  bool carry_out(const sim::Actuation& a, sim::State& state, std::vector<Push>& pushes,
                 std::vector<sim::ModuleId>& leaving);
  void step_bodies(sim::State& state, std::span<const Push> pushes, sim::WorkerPool& workers);
  bool touches_ground(const sim::Pose& pose) const;
  std::optional<sim::ModuleId> taken_by(sim::ModuleId self, const sim::Vec3& at, const sim::State& state) const;
  void set_off(const sim::Mover& mover, sim::State& state, std::vector<sim::ModuleId>& leaving);
  std::vector<sim::Bond> bonds_of(const sim::BondSet& bonds, std::span<const sim::ModuleId> modules);
  void let_go(std::span<const sim::ModuleId> leaving, sim::State& state);
  void latch(std::span<const sim::ModuleId> arrived, sim::State& state);
  // The bonds between each of `modules` and the still modules it touches. Over ranks a module's
  // neighbours are known where its list is held, its owner's window among them: each rank finds
  // its own modules' bonds, and the ranks swap them.
  std::vector<sim::Bond> touching_bonds(const sim::State& state, std::span<const sim::ModuleId> modules);
  void regroup(sim::State& state);
  void regroup_all(sim::State& state);

  PhysicsSettings settings_;
  ModuleShape shape_;
  float ground_z_;
  Dynamics dynamics_;
  ContactGraph contacts_;
  std::vector<float> force_;
  bool graph_stale_ = false;  // state.graph is not yet measured from the bodies (a module removed)
  // The bonds as they are (invalidated when a request changes them: rare), and what changed
  // since the clusters were formed.
  BondIndex bond_index_;
  BondChanges changes_;
  Regrouper regrouper_;
  // Whether the contact graph was last updated for the state being stepped on (not restored,
  // nothing regrouped from scratch since), and the modules whose pose or frame changed since.
  bool contacts_known_ = false;
  std::vector<sim::ModuleId> changed_;
  std::unique_ptr<ContactGraph> check_;
  sim::RankExchange* ranks_ = nullptr;
  sim::ModuleOwners owners_;
  std::vector<std::pair<float, sim::ModuleId>> heading_;  // (x of the target, mover), sorted; in advance
};

}  // namespace dw::physics
