#include "physics/clusters.h"

#include <algorithm>
#include <numeric>

#include <BulletCollision/CollisionShapes/btCompoundShape.h>

#include "physics/convert.h"
#include "physics/union_find.h"

namespace dw::physics {

void settle(sim::Bodies& b, sim::Cluster& c, std::span<const sim::ModuleId> mine, btCollisionShape& module_shape) {
  const uint32_t old = b.cluster_of.empty() ? sim::kNoCluster : b.cluster_of[mine[0]];
  // The same members held the same way: the frame stays (members keep their local poses).
  if (old != sim::kNoCluster && b.clusters[old].count == c.count && b.clusters[old].anchored == c.anchored &&
      std::equal(mine.begin(), mine.end(), b.members.begin() + b.clusters[old].first)) {
    c.pose = b.clusters[old].pose;
    c.velocity = b.clusters[old].velocity;
    return;
  }
  c.velocity = {};
  if (c.anchored) {
    // It never moves: the world's frame will do, and members' poses in it are their world poses
    // (Bodies::pose_in_cluster) whatever joins or leaves (a block of a million that a module
    // leaves is not walked: a member of an anchored cluster has no velocity already).
    c.pose = sim::Pose{};
    for (sim::ModuleId m : mine) {
      const uint32_t was = b.cluster_of.empty() ? sim::kNoCluster : b.cluster_of[m];
      if (was != sim::kNoCluster && b.clusters[was].anchored) continue;
      b.velocities.set(m, {});
    }
    return;
  }
  if (c.count == 1) {
    c.pose = b.poses[mine[0]];
    b.local.set(mine[0], sim::Pose{});
  } else {
    // A cluster the ground lets go of gets its principal frame too: a rigid body turns about its
    // centre of mass.
    btCompoundShape compound(false, static_cast<int>(c.count));
    for (sim::ModuleId m : mine) compound.addChildShape(to_bt(b.poses[m]), &module_shape);
    std::vector<btScalar> masses(c.count, 1);
    btTransform principal;
    btVector3 inertia;
    compound.calculatePrincipalAxisTransform(masses.data(), principal, inertia);
    c.pose = from_bt(principal);
    const btTransform frame = to_bt(c.pose), inverse = frame.inverse();
    for (sim::ModuleId m : mine) b.local.set(m, from_bt(inverse * to_bt(b.poses[m])));
  }
  // The members' mean velocity: momentum is kept when pieces join or split.
  btVector3 linear(0, 0, 0), angular(0, 0, 0);
  for (sim::ModuleId m : mine) {
    linear += to_bt(b.velocities[m].linear);
    angular += to_bt(b.velocities[m].angular);
  }
  c.velocity = {from_bt(linear / btScalar(c.count)), from_bt(angular / btScalar(c.count))};
}

void form_clusters(sim::Bodies& b, std::span<const uint8_t> present, btCollisionShape& module_shape) {
  const uint32_t n = static_cast<uint32_t>(b.poses.size());
  std::vector<uint8_t> still(present.begin(), present.end());  // present and not gliding
  for (const sim::Mover& mover : b.movers) still[mover.module] = 0;
  auto in_cluster = [&](sim::ModuleId m) { return still[m] != 0; };
  std::vector<uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  std::vector<uint8_t> grounded(n, 0);
  b.bonds.for_each([&](const sim::Bond& bond) {
    if (!in_cluster(bond.a)) return;
    if (bond.b == sim::kGround) grounded[bond.a] = 1;
    else if (in_cluster(bond.b)) {
      const uint32_t ra = find_root(parent, bond.a), rb = find_root(parent, bond.b);
      parent[std::max(ra, rb)] = std::min(ra, rb);  // the root is the smallest member
    }
  });

  // Components in the order of their smallest member, members ascending.
  std::vector<uint32_t> component(n, sim::kNoCluster), sizes;
  uint32_t count = 0;
  for (sim::ModuleId m = 0; m < n; ++m) {
    if (!in_cluster(m)) continue;
    const uint32_t r = find_root(parent, m);
    if (r == m) {
      component[m] = count++;
      sizes.push_back(0);
    } else {
      component[m] = component[r];
    }
    ++sizes[component[m]];
  }
  std::vector<sim::Cluster> clusters(count);
  std::vector<sim::ModuleId> members(std::accumulate(sizes.begin(), sizes.end(), size_t{0}));
  for (uint32_t c = 0, first = 0; c < count; first += sizes[c], ++c) clusters[c].first = first;
  for (sim::ModuleId m = 0; m < n; ++m)
    if (component[m] != sim::kNoCluster) {
      sim::Cluster& c = clusters[component[m]];
      members[c.first + c.count++] = m;
      c.anchored = c.anchored || grounded[m];
    }

  for (sim::Cluster& c : clusters) settle(b, c, std::span(members.data() + c.first, c.count), module_shape);
  b.clusters = std::move(clusters);
  b.members = std::move(members);
  b.cluster_of = {};
  b.cluster_of.resize(n);
  for (sim::ModuleId m = 0; m < n; ++m) b.cluster_of.set(m, component[m]);
}

void place_members(sim::Bodies& b) {
  for (const sim::Cluster& c : b.clusters) {
    if (c.anchored) continue;
    const btTransform frame = to_bt(c.pose);
    const btVector3 v = to_bt(c.velocity.linear), w = to_bt(c.velocity.angular);
    for (uint32_t i = c.first; i < c.first + c.count; ++i) {
      const sim::ModuleId m = b.members[i];
      const btTransform pose = frame * to_bt(b.local[m]);
      b.poses.set(m, from_bt(pose));
      b.velocities.set(m, {from_bt(v + w.cross(pose.getOrigin() - frame.getOrigin())), c.velocity.angular});
    }
  }
}

}  // namespace dw::physics
