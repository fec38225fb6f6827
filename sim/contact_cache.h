// The contact cache (docs/design.md §8a): the contact points the solver worked on in the last step,
// with the impulses it applied, kept in the state so that the next step starts from them (warm
// starting) — as MuJoCo keeps its warm start in mjData and Jolt and Box2D v3 keep theirs in a
// snapshot. Being state, it is hashed, copied into keyframes, sent between ranks and restored by a
// seek: a step stays a pure function of the state.
#pragma once

#include <cstdint>
#include <tuple>

#include "sim/vec3.h"

namespace dw::sim {

// Who touches: a module's id, the ground, or the scenario's prop i.
inline constexpr uint32_t kGroundContact = 0xffffffffu;
inline constexpr uint32_t contact_prop(uint32_t i) { return 0xfffffffeu - i; }

// One contact point between the body holding module (or prop, or ground) `a` and that holding `b`,
// as the solver left it. The points of one pair keep the solver's order; pairs are sorted by (a, b).
struct ContactPoint {
  uint32_t a = 0, b = 0;
  Vec3 local_a{}, local_b{};  // where it lies in each body's frame (a cluster's frame for its members)
  Vec3 normal{};              // on b, in the world, pointing from b to a
  float distance = 0;         // negative when they overlap
  float impulse = 0;          // accumulated normal impulse (N s)
  float friction[2]{};        // accumulated impulses along the two friction directions
  Vec3 direction[2]{};        // the friction directions, kept so that the impulses keep meaning
  uint32_t age = 0;           // steps the point has lasted
  bool operator==(const ContactPoint&) const = default;
};
// No padding: the state hash reads them bit for bit.
static_assert(sizeof(ContactPoint) == 2 * sizeof(uint32_t) + 19 * sizeof(float) + sizeof(uint32_t));

inline bool contact_pair_less(const ContactPoint& x, const ContactPoint& y) {
  return std::tie(x.a, x.b) < std::tie(y.a, y.b);
}

}  // namespace dw::sim
