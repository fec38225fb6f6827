// Copies of short id and truth arrays in fixed-size chunks: a fixed-size copy compiles to a few
// vector moves, where a copy of variable length calls memmove. Both ends need slack for the last
// chunk, which may run past `count`.
#pragma once

#include <cstdint>
#include <cstring>

namespace dw::watch {

constexpr uint32_t kCopyChunk = 4;  // 32-bit values per chunk

inline void copy_ids(uint32_t* dst, const uint32_t* src, uint32_t count) {
  for (uint32_t i = 0; i < count; i += kCopyChunk) std::memcpy(dst + i, src + i, 4 * kCopyChunk);
}

constexpr uint32_t kByteChunk = 8;

inline void copy_bytes(uint8_t* dst, const uint8_t* src, uint32_t count) {
  for (uint32_t i = 0; i < count; i += kByteChunk) std::memcpy(dst + i, src + i, kByteChunk);
}

}  // namespace dw::watch
