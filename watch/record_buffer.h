// PatternMatchers in flight, packed in one growing byte buffer. A module sends the same
// PatternMatcher to several neighbours, so a record is one PatternMatcher with its receivers:
//
//   uint32 count | uint32 receivers[count] | PatternMatcher
//
// and each receiver reads it where it lies (a receiver that fills a slot copies it first).
// Appending never allocates per message.
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

  // Appends the PatternMatcher `pm` (`bytes` long, whole 32-bit words) for the receivers in `to`
  // (readable for kCopyChunk values past its end).
  void append(std::span<const uint32_t> to, const std::byte* pm, uint32_t bytes) {
    const uint32_t count = static_cast<uint32_t>(to.size());
    const size_t need = size_ + 4 * (1 + size_t{count}) + bytes;
    if (need > capacity_) grow(need);
    std::byte* at = data_.get() + size_;
    std::memcpy(at, &count, 4);
    // Copied in chunks (see copy_ids): `to` must have room for reading a chunk past its end. What
    // the receivers' last chunk writes past them, the PatternMatcher overwrites; for its own last
    // chunk the buffer keeps slack.
    copy_ids(reinterpret_cast<uint32_t*>(at + 4), to.data(), count);
    copy_ids(reinterpret_cast<uint32_t*>(at + 4 * (1 + size_t{count})), reinterpret_cast<const uint32_t*>(pm),
             bytes / 4);
    size_ = need;
  }

  // The records, as append wrote them: size() bytes.
  const std::byte* data() const { return data_.get(); }
  // Appends records another buffer holds (data() and size() of it): whole records only.
  void append_records(const std::byte* records, size_t size) {
    if (size_ + size > capacity_) grow(size_ + size);
    if (size) std::memcpy(data_.get() + size_, records, size);
    size_ += size;
  }

  // Calls fn(receivers, pm) for every record, in order. hint(to) names the next record's first
  // receiver ahead of time, so that its state can be fetched meanwhile.
  template <class Fn, class Hint>
  void for_each(Fn&& fn, Hint&& hint) const {
    const std::byte* at = data_.get();
    const std::byte* end = at + size_;
    while (at < end) {
      uint32_t count;
      std::memcpy(&count, at, 4);
      // The buffer is 16-byte aligned and every record a whole number of 32-bit words.
      const uint32_t* to = reinterpret_cast<const uint32_t*>(at + 4);
      const std::byte* pm = at + 4 * (1 + size_t{count});
      const std::byte* next = pm + PatternMatcherRef::bytes_of(pm);
      if (next < end) {
        uint32_t next_to;
        std::memcpy(&next_to, next + 4, 4);
        hint(next_to);
      }
      fn(std::span<const uint32_t>(to, count), pm);
      at = next;
    }
  }

  // fn(to, pm, bytes) for every receiver of every record, for hashing and counting.
  template <class Fn>
  void visit(Fn&& fn) const {
    for_each(
        [&](std::span<const uint32_t> to, const std::byte* pm) {
          for (uint32_t n : to) fn(n, pm, PatternMatcherRef::bytes_of(pm));
        },
        [](uint32_t) {});
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
