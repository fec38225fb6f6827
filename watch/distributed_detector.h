// The distributed detector (paper Alg. 2, docs/design.md §4): one distributed agent per module, the
// PatternMatchers they exchange carried by an in-process transport. Consistent states, linear
// chains: slot i is filled at step t0 + i - 1 by a neighbour of the module that filled slot i - 1.
#pragma once

#include <memory>
#include <vector>

#include "watch/detector.h"
#include "watch/distributed_agents.h"
#include "watch/in_process_transport.h"
#include "watch/watchpoint.h"

namespace dw::watch {

class DistributedDetector final : public Detector {
 public:
  DistributedDetector(const Watchpoint& watchpoint, const Universe& universe, DetectorOptions options, MatchSink sink);

  void observe(const Frame& frame) override;
  // Agents that wait for their neighbours' values (an aggregate's hop) decide the last steps of
  // the input from the history they hold.
  void finish() override;
  int64_t lag() const override { return watch::lag(program_, Algorithm::Distributed, options_); }
  std::unique_ptr<Detector> clone() const override { return std::make_unique<DistributedDetector>(*this); }
  Algorithm algorithm() const override { return Algorithm::Distributed; }
  size_t bytes() const override;

 private:
  const Program& program_;
  DetectorOptions options_;
  std::vector<int> columns_;  // program variable -> frame column, -1 if frames never carry it
  DistributedAgents agents_;
  InProcessTransport transport_;
  AgentContext ctx_;
  int64_t newest_ = -1;  // the newest frame's step
  int64_t next_f_ = 0;   // the next detector step to run

  void run_step(int64_t f);
};

}  // namespace dw::watch
