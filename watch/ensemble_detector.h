// The reading of a zero-slot watchpoint (docs/design.md §4c, `modules(); φ`): φ reads constants, `all`
// aggregates and windows over them, facts of the whole ensemble at a step, so every reading
// (centralized, distributed consistent or simultaneous, any shape) decides it alike: once a step,
// at E+ behind the newest frame, a match being the step itself with no module.
#pragma once

#include <memory>

#include "watch/detector.h"
#include "watch/step_view.h"
#include "watch/watchpoint.h"

namespace dw::watch {

class EnsembleDetector final : public Detector {
 public:
  // `algorithm` is the reading asked for: the same matches whichever, it is only reported.
  EnsembleDetector(const Watchpoint& watchpoint, const Universe& universe, Algorithm algorithm, DetectorOptions options,
                   MatchSink sink);

  void observe(const Frame& frame) override;
  int64_t lag() const override { return program_->extent_plus; }
  std::unique_ptr<Detector> clone() const override { return std::make_unique<EnsembleDetector>(*this); }
  Algorithm algorithm() const override { return algorithm_; }
  size_t bytes() const override { return sizeof(*this) + history_.bytes() + view_.bytes(); }

 private:
  // Shared by clones, so that the references the parts below keep stay valid in a snapshot.
  std::shared_ptr<const Program> program_;
  Algorithm algorithm_;
  StepHistory history_;
  StepView view_;
  std::vector<Truth> leaves_, stack_;
};

}  // namespace dw::watch
