// Builds the detector of either algorithm behind the common Detector interface.
#pragma once

#include <memory>

#include "watch/detector.h"
#include "watch/watchpoint.h"

namespace dw::watch {

// `watchpoint` and `universe` must outlive the detector. The options must be supported
// (watch::unsupported).
std::unique_ptr<Detector> make_detector(Algorithm algorithm, const Watchpoint& watchpoint, const Universe& universe,
                                        DetectorOptions options, MatchSink sink);

}  // namespace dw::watch
