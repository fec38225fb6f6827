// The physical part of State (docs/design.md §2, §8): where each module is, how it moves, which modules
// are latched together. Plain data, written by a physical World (physics/) and read by programs,
// the renderer and the state hash; a static lattice leaves it empty.
//
// Modules latched by bonds form a rigid *cluster* that moves as one body: its frame (pose and
// velocity) is the state, each member's pose within it is fixed while the cluster lasts, and a
// member's world pose is derived from the two. A cluster latched to the ground is anchored: it
// does not move at all, and its frame is the world's. A module making a lattice move or a pivot
// belongs to no cluster while it moves.
#pragma once

#include <algorithm>
#include <array>
#include <compare>
#include <cstdint>
#include <limits>
#include <vector>

#include "sim/bond_set.h"
#include "sim/contact_cache.h"
#include "sim/lattice.h"
#include "sim/neighbor_graph.h"
#include "sim/paged_array.h"
#include "sim/vec3.h"

namespace dw::sim {

struct Pose {
  Vec3 position{};
  std::array<float, 4> orientation{0, 0, 0, 1};  // a unit quaternion x, y, z, w
  bool operator==(const Pose&) const = default;
};

struct Velocity {
  Vec3 linear{};
  Vec3 angular{};
  bool operator==(const Velocity&) const = default;
};

// No padding: the state hash reads them bit for bit.
static_assert(sizeof(Pose) == 7 * sizeof(float) && sizeof(Velocity) == 6 * sizeof(float));

// cluster_of for a module that belongs to no cluster (absent, or making a lattice move).
inline constexpr uint32_t kNoCluster = std::numeric_limits<uint32_t>::max();

struct Cluster {
  Pose pose;                      // the frame: centre of mass, principal axes
  Velocity velocity;              // of the centre of mass
  uint32_t first = 0, count = 0;  // its members: Bodies::members[first, first + count)
  // Steps it has been still for (physics/settings.h: sleep_after); past that, with its island, it sleeps.
  uint32_t still = 0;
  bool anchored = false;  // latched to the ground: it does not move
  bool operator==(const Cluster&) const = default;
};

// Mover::hinge of a lattice move, which turns on no module.
inline constexpr ModuleId kNoHinge = std::numeric_limits<ModuleId>::max();

// A lattice move: the module glides from one cell to the adjacent one over `steps` steps; or a
// pivot: it turns by `angle` about the line through `pivot` along `axis` (a cube about an edge it
// shares with a neighbour, a sphere rolling over a neighbour), its own body turning `spin` times
// as far (1 for a cube; 2 for a sphere rolling without slipping on one of its size). A pivot's
// `hinge` is that neighbour: it touches the mover all the turn long (along the edge, or as the
// sphere rolls on it), so the two are neighbours at every step of the turn (physics/contact_graph.h).
struct Mover {
  ModuleId module = 0;
  Pose from, to;
  int64_t start = 0;  // the first step of the glide
  int64_t steps = 1;
  Vec3 pivot{}, axis{};  // a slide has no axis
  float angle = 0, spin = 1;
  ModuleId hinge = kNoHinge;
  bool operator==(const Mover&) const = default;
};

// A module's pose until it first moves: at its lattice cell, unturned (without a lattice, at the
// origin).
struct CellPose {
  LatticeSpec lattice{};
  uint32_t on_lattice = 0;  // not a bool: serialized bit for bit, it leaves no padding
  Pose operator()(size_t m) const {
    return on_lattice ? Pose{.position = cell_position(lattice, static_cast<ModuleId>(m))} : Pose{};
  }
  bool operator==(const CellPose&) const = default;
};
static_assert(sizeof(CellPose) == sizeof(LatticeSpec) + sizeof(uint32_t));

struct Bodies {
  PagedArray<Pose, CellPose> poses;  // per module, in the world (a lattice's at rest: not kept)
  PagedArray<Velocity> velocities;   // per module: of its centre (zero at rest: not kept)
  PagedArray<Pose> local;            // per module in a cluster that moves: its pose in its frame
  // Per module, or kNoCluster. Paged with cluster 0 as the default: a latched lattice is one
  // anchored cluster, whose million members would otherwise take 4 MB on every rank.
  PagedArray<uint32_t> cluster_of;
  std::vector<Cluster> clusters;  // ordered by their smallest member
  std::vector<ModuleId> members;  // each cluster's members, ascending
  BondSet bonds;                  // who is latched to whom and to the ground
  std::vector<Mover> movers;      // sorted by module
  std::vector<Pose> prop_poses;   // the scenario's props (bodies that are not modules)
  std::vector<Velocity> prop_velocities;
  std::vector<ContactPoint> contacts;  // the warm start of the next step (sim/contact_cache.h)

  bool empty() const { return poses.empty(); }
  // A module's pose in its cluster's frame. An anchored cluster's frame is the world's, so its
  // members' is their world pose (not kept twice: a latched lattice of a million would hold 28 MB
  // of copies); a module in no cluster has the identity.
  Pose pose_in_cluster(ModuleId m) const {
    const uint32_t c = cluster_of.empty() ? kNoCluster : cluster_of[m];
    if (c == kNoCluster) return {};
    return clusters[c].anchored ? poses[m] : local[m];
  }
  // Making a lattice move.
  bool moving(ModuleId m) const {
    auto at =
        std::lower_bound(movers.begin(), movers.end(), m, [](const Mover& x, ModuleId id) { return x.module < id; });
    return at != movers.end() && at->module == m;
  }
  bool operator==(const Bodies&) const = default;
};

}  // namespace dw::sim
