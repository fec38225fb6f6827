// The centralized detector (paper Alg. 1, docs/design.md §4 and §4a): at every watch step t, every binding
// of the slots to distinct modules present at t that forms the group shape (a chain, the paper's
// prefix-connected order, or any connected group in any slot assignment) and makes the expression
// true over simultaneous states.
#pragma once

#include <memory>
#include <vector>

#include "watch/binding_search.h"
#include "watch/connected_groups.h"
#include "watch/detector.h"
#include "watch/step_view.h"
#include "watch/watchpoint.h"

namespace dw::watch {

class CentralizedDetector final : public Detector {
 public:
  CentralizedDetector(const Watchpoint& watchpoint, const Universe& universe, DetectorOptions options, MatchSink sink);

  void observe(const Frame& frame) override;
  int64_t lag() const override { return watch::lag(*program_, Algorithm::Centralized, options_); }
  std::unique_ptr<Detector> clone() const override { return std::make_unique<CentralizedDetector>(*this); }
  Algorithm algorithm() const override { return Algorithm::Centralized; }
  size_t bytes() const override;

 private:
  void run_step(int64_t t);

  // Shared by clones, so that the references the parts below keep stay valid in a snapshot;
  // a snapshot needs nothing else to outlive it.
  std::shared_ptr<const Program> program_;
  DetectorOptions options_;
  GroupShape shape_;
  StepHistory history_;
  StepView view_;
  BindingSearch search_;
  ConnectedGroups groups_;
  std::vector<uint32_t> first_;    // slot 0's candidates: the modules present at t
  std::vector<uint8_t> eligible_;  // any: modules that may fill some slot
  MatchBuffer matches_;
  std::vector<Value> actions_;  // per match, its actions' values
  StepStats step_;
};

}  // namespace dw::watch
