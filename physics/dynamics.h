// One physics step of what can move (docs/design.md §7, §8): clusters that are not anchored, modules
// making a lattice move (kinematic), and props.
//
// What Bullet would carry from one step to the next in a long-lived world — the contact points
// and the impulses that warm-start its solver — is kept in the state instead
// (sim::Bodies::contacts, physics/warm_start.h, docs/design.md §8a). A step is therefore a pure
// function of the state: the live run and a run re-simulated after a rollback compute the same
// thing, on any thread or rank count. What is kept between steps (the compound shapes of
// clusters, each batch's Bullet world with its pairs and manifolds) computes what it would compute
// made afresh from the state.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "physics/islands.h"
#include "physics/settings.h"
#include "sim/bodies.h"
#include "sim/rank_exchange.h"
#include "sim/worker_pool.h"

class btCollisionObject;
class btCollisionShape;
class btSequentialImpulseConstraintSolver;

namespace dw::physics {

// Where a lattice move or a pivot is at a step: from `from` at mover.start to `to` at start + steps.
sim::Pose glide(const sim::Mover& mover, int64_t step);
// Where a pivot is after the fraction f (0..1) of its turn.
sim::Pose turn(const sim::Mover& pivot, float f);

struct Push {
  sim::ModuleId module = 0;
  sim::Vec3 impulse{};
};

// Per box (poses in one frame, lattice cells one module apart): 1 when boxes sit across all six
// of its faces, so that nothing outside reaches it without passing through another first.
std::vector<uint8_t> enclosed_boxes(const std::vector<sim::Pose>& boxes);

class Dynamics {
 public:
  // Islands are stepped in batches of at least `batch_bodies` moving bodies (1: each island in a
  // world of its own, as the tests of island independence ask).
  static constexpr uint32_t kBatchBodies = 256;
  Dynamics(const PhysicsSettings& settings, ModuleShape shape, float ground_z, uint32_t batch_bodies = kBatchBodies);
  ~Dynamics();
  Dynamics(const Dynamics&) = delete;
  Dynamics& operator=(const Dynamics&) = delete;

  btCollisionShape& module_shape() { return *module_shape_; }
  // Nothing that Bullet moves: every cluster anchored, no prop that is not fixed (lattice moves
  // glide on their own).
  bool idle(const sim::Bodies& bodies) const;
  // Moves the clusters, props and movers from step `to - 1` to step `to`; pushes are applied
  // first. Writes each module's contact force (N) over the step from other bodies (the ground's
  // support is left out) into `force`, unless it is null (nothing asks: no bond could break).
  // Islands of bodies that cannot touch within the step (physics/islands.h) are stepped apart, in
  // batches of consecutive islands (a world for each batch), on `workers`; the result does not
  // depend on their number. Over `ranks` (a collective call, made alike on every rank with the
  // same bodies), each rank steps a run of the batches and the ranks swap what their islands
  // wrote: each ends with what one process computes, bit for bit.
  void step(sim::Bodies& bodies, std::span<const Push> pushes, int64_t to, std::vector<float>* force,
            sim::WorkerPool& workers, sim::RankExchange* ranks = nullptr);
  // Islands in the last step, and the clusters that moved in those this process stepped (over
  // ranks, its run of them), ascending.
  uint32_t islands() const { return islands_; }
  const std::vector<uint32_t>& stepped_clusters() const { return stepped_; }

 private:
  struct Compound;
  struct Body;
  struct Plan;
  struct IslandOutput;
  struct Shapes;
  struct BatchWorld;
  // Where `body` can be over the step; `travel`, if given, how far a point of it can move.
  ReachBox reach(const Body& body, float pushed, float turned, float* travel = nullptr) const;
  const Compound& compound(const sim::Bodies& bodies, const sim::Cluster& cluster, int64_t step);
  // The stages of a step, in order (dynamics.cpp).
  void gather_bodies(Plan& plan, const sim::Bodies& b, std::span<const Push> pushes, int64_t to);
  void form_islands(Plan& plan, const sim::Bodies& b, std::span<const Push> pushes) const;
  // The bodies of the batch of islands [from, to) that are awake, in tag order, each once (a fixed
  // body near two islands is in both).
  static std::vector<uint32_t> awake_bodies(const Plan& plan, uint32_t from, uint32_t to);
  // The place of the world of a batch of `bodies` (made when first stepped; a key of its own for
  // each batch of the step).
  std::unique_ptr<BatchWorld>& world_of(const Plan& plan, std::span<const uint32_t> bodies, uint32_t batch);
  void step_batch(const Plan& plan, uint32_t from, uint32_t to, std::span<const uint32_t> bodies,
                  std::unique_ptr<BatchWorld>& world, btSequentialImpulseConstraintSolver& solver, int64_t step,
                  sim::Bodies& b, bool forces, IslandOutput& out);
  static void share(const Plan& plan, uint32_t first, uint32_t last, std::vector<IslandOutput>& outputs, sim::Bodies& b,
                    sim::RankExchange& ranks);
  void settle(const Plan& plan, std::vector<IslandOutput>& outputs, sim::Bodies& b);
  static int64_t module_of(const Plan& plan, const sim::Bodies& b, const btCollisionObject* o, int child);
  int64_t sleep_after_steps() const;

  const PhysicsSettings& settings_;
  uint32_t batch_bodies_;
  std::unique_ptr<Shapes> shapes_;
  btCollisionShape* module_shape_;
  bool round_modules_;  // modules roll, and resist it (PhysicsSettings::rolling_friction)
  uint32_t islands_ = 0;
  std::vector<uint32_t> stepped_;
  // The contact cache before the last step, its memory kept for the next one's (a 20^3 pile's is
  // 8 MB, faulted in afresh each step when allocated anew). Not state: emptied before each use.
  std::vector<sim::ContactPoint> spare_contacts_;
  std::vector<IslandOutput> outputs_;  // per island, emptied before each step: likewise
};

}  // namespace dw::physics
