// PatternMatchers in flight, packed in one growing byte buffer: each record is the receiver's
// dense index followed by the PatternMatcher. Appending never allocates per message.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <span>

#include "watch/chunked_copy.h"
#include "watch/pattern_matcher.h"

namespace dw::watch {

class RecordBuffer {
 public:
  RecordBuffer() = default;
  RecordBuffer(const RecordBuffer& other) { *this = other; }
  RecordBuffer& operator=(const RecordBuffer& other) {
    if (this == &other) return *this;
    size_ = 0;
    // A copy (a snapshot) takes only the room it needs; appending grows it again.
    if (other.size_ > capacity_) grow(other.size_, other.size_);
    if (other.size_) std::memcpy(data_.get(), other.data_.get(), other.size_);
    size_ = other.size_;
    return *this;
  }
  RecordBuffer(RecordBuffer&&) = default;
  RecordBuffer& operator=(RecordBuffer&&) = default;

  size_t size() const { return size_; }
  size_t bytes() const { return capacity_ ? capacity_ + kSlack : 0; }  // held on the heap
  bool empty() const { return size_ == 0; }
  void clear() { size_ = 0; }

  // Appends one copy of `pm` (`bytes` long, whole 32-bit words) for each receiver in `to`.
  void append(std::span<const uint32_t> to, const std::byte* pm, uint32_t bytes) {
    const size_t need = size_ + to.size() * (4 + static_cast<size_t>(bytes));
    if (need > capacity_) grow(need);
    std::byte* at = data_.get() + size_;
    for (uint32_t n : to) {
      std::memcpy(at, &n, 4);
      // Copied in chunks (see copy_ids): the buffer keeps slack for the chunk past the end.
      copy_ids(reinterpret_cast<uint32_t*>(at + 4), reinterpret_cast<const uint32_t*>(pm), bytes / 4);
      at += 4 + bytes;
    }
    size_ = need;
  }

  // Calls fn(to, record) for every record in order; fn may modify the record in place. hint(to)
  // names the next record's receiver ahead of time, so that its state can be fetched meanwhile.
  template <class Fn, class Hint>
  void for_each(Fn&& fn, Hint&& hint) {
    std::byte* at = data_.get();
    std::byte* end = at + size_;
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

  // Read-only walk, for hashing and counting: fn(to, record, bytes).
  template <class Fn>
  void visit(Fn&& fn) const {
    const std::byte* at = data_.get();
    const std::byte* end = at + size_;
    while (at < end) {
      uint32_t to;
      std::memcpy(&to, at, 4);
      const uint32_t bytes = PatternMatcherRef::bytes_of(at + 4);
      fn(to, at + 4, bytes);
      at += 4 + bytes;
    }
  }

 private:
  static constexpr size_t kSlack = 16;  // for chunked copies past the last record
  void grow(size_t need, size_t first = size_t{1} << 16) {
    size_t cap = capacity_ ? capacity_ : first;
    while (cap < need) cap *= 2;
    auto bigger = std::make_unique_for_overwrite<std::byte[]>(cap + kSlack);
    if (size_) std::memcpy(bigger.get(), data_.get(), size_);
    data_ = std::move(bigger);
    capacity_ = cap;
  }

  std::unique_ptr<std::byte[]> data_;
  size_t size_ = 0;
  size_t capacity_ = 0;
};

}  // namespace dw::watch
