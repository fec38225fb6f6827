#include "physics/contact_graph.h"
#include "physics/pair_cache.h"

#include <algorithm>

#include <BulletCollision/BroadphaseCollision/btCollisionAlgorithm.h>
#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btCollisionWorld.h>
#include <BulletCollision/CollisionDispatch/btDefaultCollisionConfiguration.h>
#include <BulletCollision/CollisionDispatch/btManifoldResult.h>

#include "physics/convert.h"
#include "physics/shapes.h"

namespace dw::physics {

struct ContactGraph::Impl {
  // Carries the graph to the near callback (a plain function pointer), so that nothing is global.
  struct Dispatcher final : btCollisionDispatcher {
    Dispatcher(btCollisionConfiguration* config, Impl& owner) : btCollisionDispatcher(config), owner(owner) {}
    Impl& owner;
  };

  explicit Impl(ModuleShape kind, float threshold)
      : dispatcher(&config, *this),
        world(&dispatcher, &broadphase, &config),
        shape(make_module_shape(kind)),
        threshold(threshold) {
    // The default box-box detector reports nothing across a gap, and the sphere-sphere one
    // nothing beyond touching: GJK measures the gap for every module shape (docs/design.md §8).
    const int type = shape->getShapeType();
    dispatcher.registerCollisionCreateFunc(
        type, type, config.getCollisionAlgorithmCreateFunc(CONVEX_HULL_SHAPE_PROXYTYPE, CONVEX_HULL_SHAPE_PROXYTYPE));
    dispatcher.setNearCallback(&near_callback);
  }

  ~Impl() {
    drop_all_pairs(*world.getPairCache(), dispatcher);
    for (auto& o : objects)
      if (o) world.removeCollisionObject(o.get());
  }

  // What a pair's measurement found, kept in the pair itself (btBroadphasePair's spare field,
  // zero when the broadphase adds the pair): a cached pair costs its 32 bytes in the pair cache,
  // not a collision algorithm and a manifold of four contact points (about 1 KB, 13 pairs a module
  // in a lattice).
  enum Measured : int { kUnmeasured = 0, kApart = 1, kTouching = 2 };

  // Measures a pair again, with a fresh algorithm and manifold, when what it is measured at
  // changed or the pair is new: members of one cluster at their local poses, others at their
  // world poses. The algorithm goes once measured.
  static void near_callback(btBroadphasePair& pair, btCollisionDispatcher& d, const btDispatcherInfo& info) {
    Impl& self = static_cast<Dispatcher&>(d).owner;
    const auto* a = static_cast<const btCollisionObject*>(pair.m_pProxy0->m_clientObject);
    const auto* b = static_cast<const btCollisionObject*>(pair.m_pProxy1->m_clientObject);
    const auto ia = size_t(a->getUserIndex()), ib = size_t(b->getUserIndex());
    const bool same = self.cluster[ia] != sim::kNoCluster && self.cluster[ia] == self.cluster[ib];
    const bool changed = self.regrouped[ia] || self.regrouped[ib] || (!same && (self.moved[ia] || self.moved[ib]));
    if (pair.m_internalTmpValue != kUnmeasured && !changed) return;
    const btTransform ta = same ? to_bt(self.local[ia]) : a->getWorldTransform();
    const btTransform tb = same ? to_bt(self.local[ib]) : b->getWorldTransform();
    const btCollisionObjectWrapper wa(nullptr, a->getCollisionShape(), a, ta, -1, -1);
    const btCollisionObjectWrapper wb(nullptr, b->getCollisionShape(), b, tb, -1, -1);
    btCollisionAlgorithm* algorithm = d.findAlgorithm(&wa, &wb, nullptr, BT_CONTACT_POINT_ALGORITHMS);
    btManifoldResult result(&wa, &wb);
    algorithm->processCollision(&wa, &wb, info, &result);
    // The pair touches when any point of any of its manifolds is within the threshold.
    btManifoldArray manifolds;
    algorithm->getAllContactManifolds(manifolds);
    bool touching = false;
    for (int i = 0; i < manifolds.size() && !touching; ++i)
      for (int p = 0; p < manifolds[i]->getNumContacts() && !touching; ++p)
        touching = manifolds[i]->getContactPoint(p).getDistance() <= self.threshold;
    algorithm->~btCollisionAlgorithm();  // releases its manifold
    d.freeCollisionAlgorithm(algorithm);
    pair.m_internalTmpValue = touching ? kTouching : kApart;
    ++self.measured;
  }

  btDefaultCollisionConfiguration config;
  Dispatcher dispatcher;
  btDbvtBroadphase broadphase;
  btCollisionWorld world;
  std::unique_ptr<btCollisionShape> shape;
  float threshold;
  std::vector<std::unique_ptr<btCollisionObject>> objects;  // per module; null while absent
  std::vector<sim::Pose> last;                              // the pose each object has
  std::vector<uint32_t> cluster;                            // per module: its cluster, as last seen
  std::vector<sim::Pose> local;                             // and its pose in that cluster
  std::vector<uint8_t> moved, regrouped;
  std::vector<std::pair<sim::ModuleId, sim::ModuleId>> pairs;
  std::shared_ptr<const sim::NeighborGraph> graph;
  uint64_t measured = 0;
};

ContactGraph::ContactGraph(ModuleShape shape, float threshold) : impl_(std::make_unique<Impl>(shape, threshold)) {}
ContactGraph::~ContactGraph() = default;

void ContactGraph::reset() { impl_->graph.reset(); }

std::shared_ptr<const sim::NeighborGraph> ContactGraph::update(const sim::Bodies& bodies,
                                                               std::span<const uint8_t> present) {
  Impl& s = *impl_;
  const std::span<const sim::Pose> poses = bodies.poses;
  const size_t n = poses.size();
  const bool forget = !s.graph;
  s.objects.resize(n);
  s.last.resize(n);
  s.cluster.resize(n, sim::kNoCluster);
  s.local.resize(n);
  s.moved.assign(n, 0);
  s.regrouped.assign(n, 0);
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
    auto& object = s.objects[m];
    if (!present[m]) {
      if (object) {
        s.world.removeCollisionObject(object.get());
        object.reset();
        changed = true;
      }
      continue;
    }
    if (!object) {
      object = std::make_unique<btCollisionObject>();
      object->setCollisionShape(s.shape.get());
      object->setUserIndex(static_cast<int>(m));
      object->setWorldTransform(to_bt(poses[m]));
      s.world.addCollisionObject(object.get());
    } else if (forget || !(poses[m] == s.last[m])) {
      object->setWorldTransform(to_bt(poses[m]));
      s.world.updateSingleAabb(object.get());
    } else {
      continue;
    }
    s.last[m] = poses[m];
    s.moved[m] = 1;
    changed = true;
  }
  s.measured = 0;
  if (!changed) {
    measured_ = 0;
    return s.graph;
  }

  s.broadphase.calculateOverlappingPairs(&s.dispatcher);
  s.dispatcher.dispatchAllCollisionPairs(s.broadphase.getOverlappingPairCache(), s.world.getDispatchInfo(),
                                         &s.dispatcher);
  measured_ = s.measured;

  std::vector<std::pair<sim::ModuleId, sim::ModuleId>> pairs;
  const btBroadphasePairArray& overlapping = s.broadphase.getOverlappingPairCache()->getOverlappingPairArray();
  for (int i = 0; i < overlapping.size(); ++i) {
    if (overlapping[i].m_internalTmpValue != Impl::kTouching) continue;
    const auto a = static_cast<sim::ModuleId>(
        static_cast<const btCollisionObject*>(overlapping[i].m_pProxy0->m_clientObject)->getUserIndex());
    const auto b = static_cast<sim::ModuleId>(
        static_cast<const btCollisionObject*>(overlapping[i].m_pProxy1->m_clientObject)->getUserIndex());
    pairs.emplace_back(std::min(a, b), std::max(a, b));
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  if (s.graph && pairs == s.pairs && s.graph->module_count() == n) return s.graph;
  s.pairs = std::move(pairs);
  s.graph =
      std::make_shared<const sim::NeighborGraph>(sim::NeighborGraph::from_pairs(static_cast<uint32_t>(n), s.pairs));
  return s.graph;
}

}  // namespace dw::physics
