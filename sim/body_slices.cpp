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
  // The slices are read where the gather left them, one after the other: a vector may begin in
  // one rank's slice and end in the next.
  size_t part = 0, at = 0, left = 0;
  for (const auto& p : parts) left += p.size();
  const auto take = [&](void* into, size_t bytes) {
    if (left < bytes) throw std::logic_error("the ranks' slices of the bodies do not add up");
    left -= bytes;
    auto* out = static_cast<std::byte*>(into);
    while (bytes > 0) {
      if (at == parts[part].size()) {
        ++part;
        at = 0;
        continue;
      }
      const size_t n = std::min(bytes, parts[part].size() - at);
      std::memcpy(out, parts[part].data() + at, n);
      out += n, at += n, bytes -= n;
    }
  };
  Bodies bodies;
  each_vector(bodies, [&](auto& v) {
    uint64_t size = 0;
    take(&size, sizeof size);
    if (size > left / sizeof(v[0])) throw std::logic_error("the ranks' slices of the bodies do not add up");
    v.resize(size);
    take(v.data(), size * sizeof(v[0]));
  });
  if (left != 0) throw std::logic_error("the ranks' slices of the bodies do not add up");
  return bodies;
}

}  // namespace dw::sim
