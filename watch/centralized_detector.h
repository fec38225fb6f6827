// The centralized detector (paper Alg. 1, DESIGN §4): at every watch step t, every binding of the
// slots to distinct modules present at t such that each slot after the first is a neighbour of an
// earlier one (prefix-connected), evaluated over simultaneous states. Depth-first, so memory stays
// bounded by the watchpoint's size, not by the number of bindings.
#pragma once

#include <memory>
#include <vector>

#include "watch/detector.h"
#include "watch/step_ring.h"
#include "watch/watchpoint.h"

namespace dw::watch {

class CentralizedDetector final : public Detector {
 public:
  CentralizedDetector(const Watchpoint& watchpoint, const Universe& universe, DetectorOptions options, MatchSink sink);

  void observe(const Frame& frame) override;
  int64_t lag() const override { return watch::lag(program_, Algorithm::Centralized); }
  std::unique_ptr<Detector> clone() const override { return std::make_unique<CentralizedDetector>(*this); }
  Algorithm algorithm() const override { return Algorithm::Centralized; }
  size_t bytes() const override;

 private:
  // One variable of every module at one step.
  struct Column {
    std::vector<int64_t> value;
    std::vector<uint8_t> known;
  };
  // Presence and the neighbour graph at one step.
  struct Graph {
    std::vector<uint8_t> present;
    std::vector<uint32_t> begin, ids;
  };
  // A term resolved for the current watch step: where its module's value lives, if anywhere.
  struct ResolvedTerm {
    const int64_t* value = nullptr;
    const uint8_t* known = nullptr;
  };

  void record(const Frame& frame);
  void run_step(int64_t t);
  void extend(uint32_t slot);
  Truth compare(const Leaf& leaf, uint32_t leaf_index, uint32_t lhs_module, uint32_t rhs_module) const;
  Truth decide(const Leaf& leaf, uint32_t leaf_index) const;
  bool culled(uint32_t slot, uint32_t candidate, const Truth* leaves);
  Truth neighbor(uint32_t x_module, int offset, uint32_t y_module) const;

  Program program_;  // a copy: a snapshot of the detector needs nothing else to outlive it
  DetectorOptions options_;
  std::vector<int> columns_;               // program variable -> frame column
  std::vector<StepRing<Column>> history_;  // per program variable
  StepRing<Graph> graphs_;

  // The step being evaluated.
  int64_t t_ = 0;
  const Graph* now_ = nullptr;
  std::vector<ResolvedTerm> lhs_, rhs_;        // per leaf
  std::vector<const Graph*> graph_at_offset_;  // [offset - min_neighbor_offset]
  std::vector<uint32_t> binding_;
  uint32_t leaf_stride_ = 0;         // leaves per level, rounded up for chunked copies
  std::vector<Truth> leaves_;        // (k + 1) levels of leaf values
  std::vector<Truth> own_truth_;     // [leaf * M + module]: own leaves, decided per step
  std::vector<uint8_t> decided_at_;  // [slot * L + leaf]: 1 when that slot decides the leaf
  std::vector<Truth> stack_, trial_;
  std::vector<std::vector<uint32_t>> candidates_;  // per slot
  std::vector<uint32_t> mark_;
  uint32_t generation_ = 0;
  std::vector<uint32_t> matches_;  // dense ids; the first match_values_ are this step's
  size_t match_values_ = 0;
  StepStats step_;
};

}  // namespace dw::watch
