// A message between neighbouring modules: sent during step t, read by the receiver at t + 1.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "sim/neighbor_graph.h"

namespace dw::sim {

struct Message {
  static constexpr uint32_t kMaxWords = 8;
  ModuleId from = 0;
  ModuleId to = 0;
  uint16_t program = 0;  // the sending program's index: a program reads only its own messages
  uint16_t size = 0;     // words used
  std::array<int64_t, kMaxWords> words{};

  std::span<const int64_t> payload() const { return {words.data(), size}; }
  int64_t operator[](size_t i) const { return words[i]; }
};

// The messages to be read at one step, grouped by receiver and then by program; within a group
// in sender order, then in the order they were sent. That order is fixed by the module ids, never
// by which thread ran a sender.
struct Mailbox {
  std::vector<Message> messages;
  std::vector<uint32_t> begin;  // [module * program_count + program], module_count * program_count + 1

  std::span<const Message> of(ModuleId m, uint32_t program, uint32_t program_count) const {
    if (begin.empty()) return {};
    const size_t g = size_t{m} * program_count + program;
    return {messages.data() + begin[g], messages.data() + begin[g + 1]};
  }
};

}  // namespace dw::sim
