// Tearing down a Bullet world in linear time. Bullet removes a collision object by scanning every
// overlapping pair (btHashedOverlappingPairCache::removeOverlappingPairsContainingProxy), so a
// world of N objects in a lattice (about 13 N pairs) takes N x 13 N steps to destroy: 12 s for a
// 30^3 cube. Emptying the pair cache first, pair by pair through its hash, makes each of those
// scans empty.
#pragma once

#include <BulletCollision/BroadphaseCollision/btDispatcher.h>
#include <BulletCollision/BroadphaseCollision/btOverlappingPairCache.h>

namespace dw::physics {

inline void drop_all_pairs(btOverlappingPairCache& cache, btDispatcher& dispatcher) {
  btBroadphasePairArray& pairs = cache.getOverlappingPairArray();
  while (pairs.size() > 0) {
    const btBroadphasePair& last = pairs[pairs.size() - 1];
    cache.removeOverlappingPair(last.m_pProxy0, last.m_pProxy1, &dispatcher);  // releases its algorithm
  }
}

}  // namespace dw::physics
