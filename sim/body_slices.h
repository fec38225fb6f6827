// A keyframe's copy of the bodies (docs/design.md §12). Over ranks every rank holds the bodies
// whole and alike, so a copy needs only a slice on each rank, the bytes of its share, put back
// together by all of them when the copy is wanted. And a copy is kept in chunks, each shared with
// the copy before it when its bytes did not change: the history of a still lattice holds its
// bodies once, and one where a few modules move holds the chunks they touched.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "sim/bodies.h"
#include "sim/rank_exchange.h"

namespace dw::sim {

class BodySlice {
 public:
  // The chunks are small enough that a few modules moving among a million touch few of them, and
  // large enough that their pointers cost nothing (16 bytes in 16 KiB).
  static constexpr size_t kChunkBytes = size_t{1} << 14;

  BodySlice() = default;
  // This rank's share of the bodies as bytes: the `rank`-th of `ranks` near-equal runs of their
  // serialization (each vector's length, then its elements bit for bit). A chunk equal to the one
  // at its place in `previous` is that one.
  BodySlice(const Bodies& bodies, int rank, int ranks, const BodySlice* previous = nullptr);

  size_t size() const { return size_; }
  // The bytes of the chunks that are not `previous`'s (all of them without one): what this copy
  // adds to the history when it follows `previous`. A chunk is shared only with the copy it
  // followed when it was made, and copies are dropped, never reordered, so each chunk of a
  // history is counted once by summing this over its copies in order.
  size_t bytes_beyond(const BodySlice* previous) const;
  // The slice's bytes, in order, a chunk at a time.
  const std::vector<std::shared_ptr<const std::vector<std::byte>>>& chunks() const { return chunks_; }

 private:
  std::vector<std::shared_ptr<const std::vector<std::byte>>> chunks_;
  size_t size_ = 0;
};

// The bodies put together from every rank's slice: over several ranks a collective call (each
// rank gives its own), in one process (`ranks` null or of one) the slice is the whole.
Bodies bodies_from_slices(const BodySlice& mine, RankExchange* ranks);

}  // namespace dw::sim
