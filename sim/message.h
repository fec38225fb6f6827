// A message between neighbouring modules: sent during step t, read by the receiver at t + 1.
//
// Messages are kept compactly (MessageList): a 16-byte header each and only the words used, so a
// one-word message takes 24 bytes rather than the 80 of a fixed eight-word record. A run whose
// million modules each send to six neighbours holds six million messages in its inbox and as many
// in its outboxes at every step.
#pragma once

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <span>
#include <vector>

#include "sim/neighbor_graph.h"

namespace dw::sim {

// One message as a program reads it: a view of its words where its list keeps them.
struct Message {
  static constexpr uint32_t kMaxWords = 8;
  ModuleId from = 0;
  ModuleId to = 0;
  uint16_t program = 0;  // the sending program's index: a program reads only its own messages
  uint16_t size = 0;     // words used
  const int64_t* words = nullptr;

  std::span<const int64_t> payload() const { return {words, size}; }
  int64_t operator[](size_t i) const { return words[i]; }
};

// What a list keeps of a message beside its words: where they start in the list's words.
struct MessageHeader {
  ModuleId from = 0;
  ModuleId to = 0;
  uint16_t program = 0;
  uint16_t size = 0;
  uint32_t first = 0;
};

// Messages in an order of their headers, read as Message views (by value).
class Messages {
 public:
  class iterator {
   public:
    using iterator_category = std::random_access_iterator_tag;
    using value_type = Message;
    using difference_type = std::ptrdiff_t;
    iterator() = default;
    iterator(const MessageHeader* at, const int64_t* words) : at_(at), words_(words) {}
    Message operator*() const { return {at_->from, at_->to, at_->program, at_->size, words_ + at_->first}; }
    iterator& operator++() { return ++at_, *this; }
    iterator operator++(int) { return {at_++, words_}; }
    difference_type operator-(const iterator& o) const { return at_ - o.at_; }
    bool operator==(const iterator& o) const { return at_ == o.at_; }

   private:
    const MessageHeader* at_ = nullptr;
    const int64_t* words_ = nullptr;
  };

  Messages() = default;
  Messages(std::span<const MessageHeader> headers, const int64_t* words) : headers_(headers), words_(words) {}
  size_t size() const { return headers_.size(); }
  bool empty() const { return headers_.empty(); }
  Message operator[](size_t i) const { return *iterator(&headers_[i], words_); }
  Message front() const { return (*this)[0]; }
  iterator begin() const { return {headers_.data(), words_}; }
  iterator end() const { return {headers_.data() + headers_.size(), words_}; }
  Messages subspan(size_t from, size_t count) const { return {headers_.subspan(from, count), words_}; }

 private:
  std::span<const MessageHeader> headers_;
  const int64_t* words_ = nullptr;
};

// Messages stored compactly, in the order added.
class MessageList {
 public:
  size_t size() const { return headers_.size(); }
  bool empty() const { return headers_.empty(); }
  Messages all() const { return {headers_, words_.data()}; }
  Message operator[](size_t i) const { return all()[i]; }
  Messages::iterator begin() const { return all().begin(); }
  Messages::iterator end() const { return all().end(); }

  void add(ModuleId from, ModuleId to, uint16_t program, std::span<const int64_t> payload);
  void add(const Message& m) { add(m.from, m.to, m.program, m.payload()); }
  // Keeps the first n messages (n <= size()).
  void keep_first(size_t n);
  void clear() {
    headers_.clear();
    words_.clear();
  }
  // Room for n messages of `words` words in all.
  void reserve(size_t n, size_t words) {
    headers_.reserve(n);
    words_.reserve(words);
  }

  // For a mailbox, which places headers itself (grouping them) over words it adds.
  std::vector<MessageHeader>& headers() { return headers_; }
  std::span<const MessageHeader> headers() const { return headers_; }
  std::vector<int64_t>& words() { return words_; }
  // The bytes the messages take, as the header and words of each (bytes() is what is reserved).
  size_t used_bytes() const { return headers_.size() * sizeof(MessageHeader) + words_.size() * sizeof(int64_t); }
  size_t bytes() const { return headers_.capacity() * sizeof(MessageHeader) + words_.capacity() * sizeof(int64_t); }

 private:
  std::vector<MessageHeader> headers_;
  std::vector<int64_t> words_;
};

// The messages to be read at one step, grouped by receiver and then by program; within a group
// in sender order, then in the order they were sent. That order is fixed by the module ids, never
// by which thread ran a sender. (Headers in that order; their words in the order they came.)
struct Mailbox {
  MessageList messages;
  std::vector<uint32_t> begin;  // [module * program_count + program], module_count * program_count + 1

  Messages of(ModuleId m, uint32_t program, uint32_t program_count) const {
    if (begin.empty()) return {};
    const size_t g = size_t{m} * program_count + program;
    return messages.all().subspan(begin[g], begin[g + 1] - begin[g]);
  }
};

}  // namespace dw::sim
