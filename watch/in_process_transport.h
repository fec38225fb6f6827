// Delivers PatternMatchers between agents in one process: everything sent during step f arrives
// at step f + 1 (the paper's one-step message latency). Records are packed in one growing buffer,
// so sending never allocates per message.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>

#include "watch/distributed_agent.h"

namespace dw::watch {

class InProcessTransport final : public PatternMatcherOutbox {
 public:
  void send(uint32_t /*from*/, std::span<const uint32_t> to, const std::byte* pm, uint32_t bytes) override {
    const size_t need = sending_.size + to.size() * (4 + static_cast<size_t>(bytes));
    if (need > sending_.capacity) sending_.grow(need);
    std::byte* at = sending_.data.get() + sending_.size;
    for (uint32_t n : to) {
      std::memcpy(at, &n, 4);
      // Records are whole 32-bit words: copy them in chunks (see copy_ids); the buffers keep
      // slack for the chunk that runs past the end.
      copy_ids(reinterpret_cast<uint32_t*>(at + 4), reinterpret_cast<const uint32_t*>(pm), bytes / 4);
      at += 4 + bytes;
    }
    sending_.size = need;
  }

  // Ends a step: what was sent becomes what is delivered.
  void deliver() {
    std::swap(sending_, delivering_);
    sending_.size = 0;
  }

  // Calls fn(to, record) for every PatternMatcher delivered at this step; the receiver may
  // modify the record in place. hint(to) names the next record's receiver ahead of time, so
  // that its state can be fetched while this one is handled.
  template <class Fn, class Hint>
  void for_each_delivered(Fn&& fn, Hint&& hint) {
    std::byte* at = delivering_.data.get();
    std::byte* end = at + delivering_.size;
    while (at < end) {
      uint32_t to;
      std::memcpy(&to, at, 4);
      std::byte* next = at + 4 + PatternMatcherRef::bytes_of(at + 4);
      if (next < end) {
        uint32_t next_to;
        std::memcpy(&next_to, next, 4);
        hint(next_to);
      }
      fn(to, at + 4);
      at = next;
    }
  }

 private:
  struct Buffer {
    std::unique_ptr<std::byte[]> data;
    size_t size = 0;
    size_t capacity = 0;
    static constexpr size_t kSlack = 16;  // for chunked copies past the last record
    void grow(size_t need) {
      size_t cap = capacity ? capacity : 1 << 16;
      while (cap < need) cap *= 2;
      auto bigger = std::make_unique_for_overwrite<std::byte[]>(cap + kSlack);
      if (size) std::memcpy(bigger.get(), data.get(), size);
      data = std::move(bigger);
      capacity = cap;
    }
  };
  Buffer sending_, delivering_;
};

}  // namespace dw::watch
