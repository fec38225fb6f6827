#include "physics/contact_graph.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <BulletCollision/CollisionShapes/btConvexShape.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpaPenetrationDepthSolver.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkPairDetector.h>
#include <BulletCollision/NarrowPhaseCollision/btVoronoiSimplexSolver.h>

#include "physics/cell_grid.h"
#include "physics/convert.h"
#include "physics/shapes.h"

namespace dw::physics {
namespace {

// The smallest distance GJK reports between two shapes (negative: they overlap).
struct ClosestDistance final : btDiscreteCollisionDetectorInterface::Result {
  btScalar distance = BT_LARGE_FLOAT;
  void setShapeIdentifiersA(int, int) override {}
  void setShapeIdentifiersB(int, int) override {}
  void addContactPoint(const btVector3&, const btVector3&, btScalar depth) override {
    distance = std::min(distance, depth);
  }
};

float squared_distance(const sim::Vec3& a, const sim::Vec3& b) {
  const float x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
  return x * x + y * y + z * z;
}

}  // namespace

struct ContactGraph::Impl {
  Impl(ModuleShape kind, float threshold)
      : shape(make_module_shape(kind)),
        convex(static_cast<btConvexShape*>(shape.get())),
        threshold(threshold),
        cutoff(reach(*shape, threshold)),
        grid(cutoff) {}

  // Centres further apart than this cannot be within the threshold: twice the radius of the
  // sphere around a module's shape, plus the threshold.
  static float reach(btCollisionShape& shape, float threshold) {
    btVector3 centre;
    btScalar radius = 0;
    shape.getBoundingSphere(centre, radius);
    return 2 * (radius + centre.length()) + threshold;
  }

  // Two modules touch when GJK puts their shapes (margins included: shapes one size apart are at
  // distance 0) at most the threshold apart. Members of one cluster are measured at their poses
  // in the cluster's frame, others at their world poses.
  bool touching(sim::ModuleId a, sim::ModuleId b, const sim::Bodies& bodies) const {
    const bool same = cluster[a] != sim::kNoCluster && cluster[a] == cluster[b];
    btGjkPairDetector::ClosestPointInput input;
    input.m_transformA = to_bt(same ? local[a] : bodies.poses[a]);
    input.m_transformB = to_bt(same ? local[b] : bodies.poses[b]);
    // GJK stops early on a pair it finds further apart than this.
    const btScalar reported = 2 * convex->getMargin() + threshold;
    input.m_maximumDistanceSquared = reported * reported;
    btVoronoiSimplexSolver simplex;
    btGjkEpaPenetrationDepthSolver depth;
    btGjkPairDetector gjk(convex, convex, &simplex, &depth);
    ClosestDistance result;
    gjk.getClosestPoints(input, result, nullptr);
    return result.distance <= threshold;
  }

  std::unique_ptr<btCollisionShape> shape;
  btConvexShape* convex;
  float threshold, cutoff;
  CellGrid grid;                                               // every present module, at its position in `last`
  std::vector<uint8_t> in_grid;                                // per module
  std::vector<sim::Pose> last;                                 // the pose each module was measured at
  std::vector<uint32_t> cluster;                               // per module: its cluster, as last seen
  std::vector<sim::Pose> local;                                // and its pose in that cluster
  std::vector<uint8_t> moved, regrouped;                       // since the last update
  bool pending = false;                                        // some flag above is set
  std::vector<std::pair<sim::ModuleId, sim::ModuleId>> pairs;  // touching, sorted
  std::shared_ptr<const sim::NeighborGraph> graph;
};

ContactGraph::ContactGraph(ModuleShape shape, float threshold) : impl_(std::make_unique<Impl>(shape, threshold)) {}
ContactGraph::~ContactGraph() = default;

void ContactGraph::reset() {
  impl_->graph.reset();
  impl_->pending = false;
  impl_->grid.clear();
  impl_->in_grid.assign(impl_->in_grid.size(), 0);
  impl_->pairs.clear();
}

bool ContactGraph::place(const sim::Bodies& bodies, std::span<const uint8_t> present) {
  Impl& s = *impl_;
  const std::span<const sim::Pose> poses = bodies.poses;
  const size_t n = poses.size();
  const bool forget = !s.graph;
  s.in_grid.resize(n, 0);
  s.last.resize(n);
  s.cluster.resize(n, sim::kNoCluster);
  s.local.resize(n);
  s.moved.resize(n, 0);
  s.regrouped.resize(n, 0);
  bool changed = forget;
  for (size_t m = 0; m < n; ++m) {
    const uint32_t c = bodies.cluster_of.empty() ? sim::kNoCluster : bodies.cluster_of[m];
    const sim::Pose local = c == sim::kNoCluster ? sim::Pose{} : bodies.local[m];
    if (forget || c != s.cluster[m] || !(local == s.local[m])) {
      s.cluster[m] = c;
      s.local[m] = local;
      s.regrouped[m] = 1;
      changed = true;
    }
  }
  for (size_t m = 0; m < n; ++m) {
    const auto id = static_cast<sim::ModuleId>(m);
    if (!present[m]) {
      if (s.in_grid[m]) {
        s.grid.erase(id, s.last[m].position);
        s.in_grid[m] = 0;
        s.moved[m] = 1;  // its pairs go
        changed = true;
      }
      continue;
    }
    if (!s.in_grid[m]) {
      s.grid.insert(id, poses[m].position);
      s.in_grid[m] = 1;
    } else if (forget || !(poses[m] == s.last[m])) {
      s.grid.move(id, s.last[m].position, poses[m].position);
    } else {
      continue;
    }
    s.last[m] = poses[m];
    s.moved[m] = 1;
    changed = true;
  }
  s.pending |= changed;
  return changed;
}

std::vector<sim::ModuleId> ContactGraph::near(const sim::Vec3& at, float radius) const {
  const Impl& s = *impl_;
  std::vector<sim::ModuleId> found;
  s.grid.around(at, [&](sim::ModuleId m) {
    if (squared_distance(s.last[m].position, at) < radius * radius) found.push_back(m);
  });
  std::sort(found.begin(), found.end());
  return found;
}

std::shared_ptr<const sim::NeighborGraph> ContactGraph::update(const sim::Bodies& bodies,
                                                               std::span<const uint8_t> present,
                                                               sim::WorkerPool& workers) {
  Impl& s = *impl_;
  const std::span<const sim::Pose> poses = bodies.poses;
  const size_t n = poses.size();
  const bool forget = !s.graph;
  place(bodies, present);
  const bool changed = std::exchange(s.pending, false);
  measured_ = 0;
  if (!changed) return s.graph;

  // A pair is measured again when what it is measured at changed: for members of one cluster,
  // their places in it; for others, their world poses. Every other pair keeps its measurement.
  const auto stale = [&](sim::ModuleId a, sim::ModuleId b) {
    if (!present[a] || !present[b] || s.regrouped[a] || s.regrouped[b]) return true;
    const bool same = s.cluster[a] != sim::kNoCluster && s.cluster[a] == s.cluster[b];
    return !same && (s.moved[a] || s.moved[b]);
  };
  std::vector<std::pair<sim::ModuleId, sim::ModuleId>> pairs;
  if (!forget)
    for (const auto& [a, b] : s.pairs)
      if (!stale(a, b)) pairs.emplace_back(a, b);
  // Each worker measures the stale pairs of a run of modules; the runs are joined in order.
  const float cutoff2 = s.cutoff * s.cutoff;
  const unsigned runs = workers.size();
  std::vector<std::vector<std::pair<sim::ModuleId, sim::ModuleId>>> found(runs);
  std::vector<uint64_t> measured(runs, 0);
  workers.run([&](unsigned run) {
    for (size_t m = n * run / runs; m < n * (run + 1) / runs; ++m) {
      if (!present[m] || !(s.moved[m] || s.regrouped[m])) continue;
      const auto a = static_cast<sim::ModuleId>(m);
      s.grid.around(poses[a].position, [&](sim::ModuleId b) {
        if (b == a || !stale(a, b)) return;
        if (b < a && (s.moved[b] || s.regrouped[b])) return;  // measured from b's side
        if (squared_distance(poses[a].position, poses[b].position) > cutoff2) return;
        ++measured[run];
        if (s.touching(a, b, bodies)) found[run].emplace_back(std::min(a, b), std::max(a, b));
      });
    }
  });
  for (unsigned run = 0; run < runs; ++run) {
    pairs.insert(pairs.end(), found[run].begin(), found[run].end());
    measured_ += measured[run];
  }
  std::sort(pairs.begin(), pairs.end());
  s.moved.assign(n, 0);
  s.regrouped.assign(n, 0);
  if (s.graph && pairs == s.pairs && s.graph->module_count() == n) return s.graph;
  s.pairs = std::move(pairs);
  s.graph =
      std::make_shared<const sim::NeighborGraph>(sim::NeighborGraph::from_pairs(static_cast<uint32_t>(n), s.pairs));
  return s.graph;
}

}  // namespace dw::physics
