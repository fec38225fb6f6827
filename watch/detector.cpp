#include "watch/detector.h"

#include <algorithm>

namespace dw::watch {

const char* algorithm_name(Algorithm a) { return a == Algorithm::Centralized ? "centralized" : "distributed"; }

void DetectorStats::add(const StepStats& s) {
  if (created_by_filled.size() < s.live_by_filled.size()) created_by_filled.resize(s.live_by_filled.size());
  for (size_t i = 0; i < s.live_by_filled.size(); ++i) created_by_filled[i] += s.live_by_filled[i];
  created += s.created;
  messages += s.messages;
  bytes += s.bytes;
  matches += s.matches;
  peak_live = std::max(peak_live, s.live);
  seconds += s.seconds;
  steps.push_back(s);
}

}  // namespace dw::watch
