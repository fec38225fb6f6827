#include "sim/message.h"

#include <stdexcept>

namespace dw::sim {

void MessageList::add(ModuleId from, ModuleId to, uint16_t program, std::span<const int64_t> payload) {
  // A header finds its words by a 32-bit index: 4 billion words, 32 GB of them, in one list.
  if (words_.size() + payload.size() > UINT32_MAX) throw std::length_error("more message words than a list indexes");
  headers_.push_back({from, to, program, static_cast<uint16_t>(payload.size()), static_cast<uint32_t>(words_.size())});
  words_.insert(words_.end(), payload.begin(), payload.end());
}

void MessageList::keep_first(size_t n) {
  if (n >= headers_.size()) return;
  words_.resize(headers_[n].first);  // the words come in the order the messages were added
  headers_.resize(n);
}

}  // namespace dw::sim
