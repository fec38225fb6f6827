// A rank's share of the bodies (docs/design.md §12): every rank of a physics run holds the bodies
// whole and alike, so a copy of them kept for later (a keyframe) needs only a slice on each rank,
// the bytes of its share, put back together by all of them when the copy is wanted.
#pragma once

#include <cstddef>
#include <vector>

#include "sim/bodies.h"
#include "sim/rank_exchange.h"

namespace dw::sim {

// This rank's share of the bodies as bytes: the `rank`-th of `ranks` near-equal runs of their
// serialization (each vector's length, then its elements bit for bit).
std::vector<std::byte> body_slice(const Bodies& bodies, int rank, int ranks);
// The bodies put together from every rank's slice (a collective call: each rank gives its own).
Bodies bodies_from_slices(std::span<const std::byte> mine, RankExchange& ranks);

}  // namespace dw::sim
