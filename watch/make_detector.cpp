#include "watch/make_detector.h"

#include "watch/centralized_detector.h"
#include "watch/distributed_detector.h"
#include "watch/ensemble_detector.h"
#include "watch/simultaneous_detector.h"

namespace dw::watch {

std::unique_ptr<Detector> make_detector(Algorithm algorithm, const Watchpoint& watchpoint, const Universe& universe,
                                        DetectorOptions options, MatchSink sink) {
  if (watchpoint.program.slot_count() == 0)  // docs/design.md §4c: every reading decides it alike
    return std::make_unique<EnsembleDetector>(watchpoint, universe, algorithm, options, std::move(sink));
  if (algorithm == Algorithm::Centralized)
    return std::make_unique<CentralizedDetector>(watchpoint, universe, options, std::move(sink));
  if (simultaneous(algorithm, options))
    return std::make_unique<SimultaneousDetector>(watchpoint, universe, options, std::move(sink));
  return std::make_unique<DistributedDetector>(watchpoint, universe, options, std::move(sink));
}

}  // namespace dw::watch
