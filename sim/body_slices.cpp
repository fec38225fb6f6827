#include "sim/body_slices.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <type_traits>

namespace dw::sim {
namespace {

// Every vector of the bodies, in the order they are serialized.
template <class B, class F>
void each_vector(B& b, F&& f) {
  f(b.poses);
  f(b.velocities);
  f(b.local);
  f(b.cluster_of);
  f(b.clusters);
  f(b.members);
  f(b.bonds);
  f(b.movers);
  f(b.prop_poses);
  f(b.prop_velocities);
}

}  // namespace

std::vector<std::byte> body_slice(const Bodies& bodies, int rank, int ranks) {
  uint64_t total = 0;
  each_vector(bodies, [&](const auto& v) { total += sizeof(uint64_t) + v.size() * sizeof(v[0]); });
  const uint64_t first = total * uint64_t(rank) / uint64_t(ranks), last = total * uint64_t(rank + 1) / uint64_t(ranks);
  std::vector<std::byte> slice(last - first);
  uint64_t at = 0;  // where the piece being laid down starts in the whole
  const auto lay = [&](const void* piece, uint64_t bytes) {
    const uint64_t from = std::max(at, first), to = std::min(at + bytes, last);
    if (from < to)
      std::memcpy(slice.data() + (from - first), static_cast<const std::byte*>(piece) + (from - at), to - from);
    at += bytes;
  };
  each_vector(bodies, [&](const auto& v) {
    static_assert(std::is_trivially_copyable_v<std::decay_t<decltype(v[0])>>);
    const uint64_t size = v.size();
    lay(&size, sizeof size);
    lay(v.data(), size * sizeof(v[0]));
  });
  return slice;
}

Bodies bodies_from_slices(std::span<const std::byte> mine, RankExchange& ranks) {
  const Gathered parts = ranks.all_gather(mine);
  std::vector<std::byte> whole;
  for (size_t r = 0; r < parts.size(); ++r) whole.insert(whole.end(), parts[r].begin(), parts[r].end());
  Bodies bodies;
  size_t at = 0;
  const auto take = [&](void* into, size_t bytes) {
    if (whole.size() - at < bytes) throw std::logic_error("the ranks' slices of the bodies do not add up");
    if (bytes) std::memcpy(into, whole.data() + at, bytes);
    at += bytes;
  };
  each_vector(bodies, [&](auto& v) {
    uint64_t size = 0;
    take(&size, sizeof size);
    if (size > (whole.size() - at) / sizeof(v[0]))
      throw std::logic_error("the ranks' slices of the bodies do not add up");
    v.resize(size);
    take(v.data(), size * sizeof(v[0]));
  });
  if (at != whole.size()) throw std::logic_error("the ranks' slices of the bodies do not add up");
  return bodies;
}

}  // namespace dw::sim
