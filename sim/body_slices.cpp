#include "sim/body_slices.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <type_traits>

namespace dw::sim {
namespace {

template <class T>
constexpr bool kPaged = false;
template <class T, class D>
constexpr bool kPaged<PagedArray<T, D>> = true;

// Every vector (or paged array) of the bodies, in the order they are serialized.
template <class B, class F>
void each_vector(B& b, F&& f) {
  f(b.poses);
  f(b.velocities);
  f(b.local);
  f(b.cluster_of);
  f(b.clusters);
  f(b.members);
  b.bonds.each_part(f);
  f(b.movers);
  f(b.prop_poses);
  f(b.prop_velocities);
  f(b.contacts);
}

// The bodies read back from their serialization, which lies in `parts` one after the other: a
// vector may begin in one part and end in the next.
template <class Parts>
Bodies read_bodies(const Parts& parts) {
  size_t part = 0, at = 0, left = 0;
  for (const auto& p : parts) left += p.size();
  const auto take = [&](void* into, size_t bytes) {
    if (left < bytes) throw std::logic_error("the slices of the bodies do not add up");
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
    if constexpr (kPaged<std::decay_t<decltype(v)>>) {
      v.read(take, left);
    } else {
      uint64_t size = 0;
      take(&size, sizeof size);
      if (size > left / sizeof(v[0])) throw std::logic_error("the slices of the bodies do not add up");
      v.resize(size);
      take(v.data(), size * sizeof(v[0]));
    }
  });
  if (left != 0) throw std::logic_error("the slices of the bodies do not add up");
  return bodies;
}

}  // namespace

BodySlice::BodySlice(const Bodies& bodies, int rank, int ranks, const BodySlice* previous) {
  uint64_t total = 0;
  each_vector(bodies, [&](const auto& v) {
    if constexpr (kPaged<std::decay_t<decltype(v)>>) total += v.written_bytes();
    else total += sizeof(uint64_t) + v.size() * sizeof(v[0]);
  });
  const uint64_t first = total * uint64_t(rank) / uint64_t(ranks), last = total * uint64_t(rank + 1) / uint64_t(ranks);
  size_ = last - first;
  chunks_.reserve((size_ + kChunkBytes - 1) / kChunkBytes);
  // The chunk being filled; when full it becomes the previous copy's chunk at its place, if equal,
  // or a chunk of its own.
  std::vector<std::byte> chunk;
  chunk.reserve(std::min<size_t>(size_, kChunkBytes));
  const auto close_chunk = [&] {
    const size_t index = chunks_.size();
    if (previous && index < previous->chunks_.size() && *previous->chunks_[index] == chunk) {
      chunks_.push_back(previous->chunks_[index]);
      chunk.clear();
      return;
    }
    chunks_.push_back(std::make_shared<const std::vector<std::byte>>(std::move(chunk)));
    chunk = {};
    if (const size_t done = chunks_.size() * kChunkBytes; done < size_)
      chunk.reserve(std::min(size_ - done, kChunkBytes));
  };
  uint64_t at = 0;  // where the piece being laid down starts in the whole
  const auto lay = [&](const void* piece, uint64_t bytes) {
    uint64_t from = std::max(at, first);
    const uint64_t to = std::min(at + bytes, last);
    while (from < to) {
      const uint64_t n = std::min<uint64_t>(to - from, kChunkBytes - chunk.size());
      const auto* p = static_cast<const std::byte*>(piece) + (from - at);
      chunk.insert(chunk.end(), p, p + n);
      from += n;
      if (chunk.size() == kChunkBytes) close_chunk();
    }
    at += bytes;
  };
  each_vector(bodies, [&](const auto& v) {
    if constexpr (kPaged<std::decay_t<decltype(v)>>) {
      v.write(lay);
    } else {
      static_assert(std::is_trivially_copyable_v<std::decay_t<decltype(v[0])>>);
      const uint64_t size = v.size();
      lay(&size, sizeof size);
      lay(v.data(), size * sizeof(v[0]));
    }
  });
  if (!chunk.empty()) close_chunk();
}

size_t BodySlice::bytes_beyond(const BodySlice* previous) const {
  size_t bytes = 0;
  for (size_t i = 0; i < chunks_.size(); ++i)
    if (!previous || i >= previous->chunks_.size() || previous->chunks_[i] != chunks_[i]) bytes += chunks_[i]->size();
  return bytes;
}

Bodies bodies_from_slices(const BodySlice& mine, RankExchange* ranks) {
  if (!ranks || ranks->ranks() == 1) {
    std::vector<std::span<const std::byte>> parts;
    for (const auto& chunk : mine.chunks()) parts.emplace_back(*chunk);
    return read_bodies(parts);
  }
  std::vector<std::byte> bytes;
  bytes.reserve(mine.size());
  for (const auto& chunk : mine.chunks()) bytes.insert(bytes.end(), chunk->begin(), chunk->end());
  const Gathered parts = ranks->all_gather(bytes);
  bytes = {};
  return read_bodies(parts);
}

}  // namespace dw::sim
