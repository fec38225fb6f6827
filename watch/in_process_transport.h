// Delivers PatternMatchers between agents in one process: everything sent during step f arrives
// at step f + 1 (the paper's one-step message latency).
#pragma once

#include <utility>

#include "watch/distributed_agents.h"
#include "watch/record_buffer.h"

namespace dw::watch {

class InProcessTransport final : public PatternMatcherOutbox {
 public:
  void send(uint32_t /*from*/, std::span<const uint32_t> to, const std::byte* pm, uint32_t bytes) override {
    sending_.append(to, pm, bytes);
  }

  // Ends a step: what was sent becomes what is delivered.
  void deliver() {
    std::swap(sending_, delivering_);
    sending_.clear();
  }

  // The PatternMatchers delivered at this step (see RecordBuffer).
  RecordBuffer& delivered() { return delivering_; }

 private:
  RecordBuffer sending_, delivering_;
};

}  // namespace dw::watch
