#include "watch/detector.h"

#include <algorithm>

#include "watch/program.h"

namespace dw::watch {

int64_t lag(const Program& program, Algorithm algorithm) {
  return program.extent_plus + (algorithm == Algorithm::Distributed ? program.slot_count() - 1 : 0);
}

std::vector<int> variable_columns(const Program& program, const Universe& universe) {
  std::vector<int> columns;
  for (const std::string& name : program.variables) {
    const auto it = std::find(universe.variables.begin(), universe.variables.end(), name);
    columns.push_back(it == universe.variables.end() ? -1 : static_cast<int>(it - universe.variables.begin()));
  }
  return columns;
}

Detector::Detector(const Universe& universe, MatchSink sink) : universe_(universe), sink_(std::move(sink)) {
  for (uint32_t m = 0; m < universe.module_count(); ++m) dense_ids_are_ids_ &= universe.module_ids[m] == m;
}

void Detector::emit(int64_t t, std::span<const uint32_t> dense) {
  if (dense.empty()) return;
  if (dense_ids_are_ids_) return sink_(t, dense);
  ids_.resize(dense.size());
  for (size_t i = 0; i < ids_.size(); ++i) ids_[i] = universe_.module_ids[dense[i]];
  sink_(t, ids_);
}

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
  last = s;
  if (steps.size() < max_steps) steps.push_back(s);
  else steps_truncated = true;
}

}  // namespace dw::watch
