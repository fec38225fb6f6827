#include "watch/detector.h"

#include <algorithm>

#include "watch/program.h"

namespace dw::watch {

int64_t lag(const Program& program, Algorithm algorithm, const DetectorOptions& options) {
  // A zero-slot watchpoint is decided whole in every reading (watch/ensemble_detector.h).
  if (algorithm == Algorithm::Centralized || program.slot_count() == 0) return program.extent_plus;
  if (simultaneous(algorithm, options))
    return program.agent_delay() + hop_latency(group_shape(algorithm, options), program.slot_count());
  return program.agent_delay() + program.slot_count() - 1;
}

const char* shape_name(GroupShape s) {
  switch (s) {
    case GroupShape::Chain: return "chain";
    case GroupShape::Ordered: return "ordered";
    case GroupShape::Any: return "any";
  }
  return "?";
}

std::optional<GroupShape> parse_shape(std::string_view name) {
  for (GroupShape s : kShapes)
    if (name == shape_name(s)) return s;
  return std::nullopt;
}

const char* states_name(States s) { return s == States::Consistent ? "consistent" : "simultaneous"; }

std::optional<States> parse_states(std::string_view name) {
  for (States s : kStates)
    if (name == states_name(s)) return s;
  return std::nullopt;
}

GroupShape group_shape(Algorithm algorithm, const DetectorOptions& options) {
  if (options.shape) return *options.shape;
  return algorithm == Algorithm::Centralized ? GroupShape::Ordered : GroupShape::Chain;
}

bool simultaneous(Algorithm algorithm, const DetectorOptions& options) {
  return algorithm == Algorithm::Distributed && options.states == States::Simultaneous;
}

std::string unsupported(Algorithm algorithm, const DetectorOptions& options) {
  if (algorithm == Algorithm::Centralized) {
    if (options.states == States::Consistent)
      return "the centralized detector compares simultaneous states; states = \"consistent\" is the distributed "
             "algorithm's";
    return "";
  }
  const GroupShape shape = group_shape(algorithm, options);
  if (!simultaneous(algorithm, options) && shape != GroupShape::Chain)
    return std::string("shape \"") + shape_name(shape) +
           "\" needs states = \"simultaneous\": the paper's distributed algorithm (consistent states) finds only "
           "chains";
  return "";
}

int64_t hop_latency(GroupShape shape, int slots) {
  const int64_t k = slots;
  return shape == GroupShape::Chain ? k - 1 : k * (k - 1) / 2;
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
  // A lattice's universe lists no ids (each is its index); a trace's lists them, in any order.
  for (uint32_t m = 0; m < universe.module_ids.size(); ++m) dense_ids_are_ids_ &= universe.module_ids[m] == m;
}

void Detector::emit(int64_t t, std::span<const uint32_t> dense, std::span<const Value> actions) {
  if (dense.empty()) return;
  if (dense_ids_are_ids_) return sink_(t, dense, actions);
  ids_.resize(dense.size());
  for (size_t i = 0; i < ids_.size(); ++i) ids_[i] = universe_.id(dense[i]);
  sink_(t, ids_, actions);
}

const char* algorithm_name(Algorithm a) { return a == Algorithm::Centralized ? "centralized" : "distributed"; }

std::optional<Algorithm> parse_algorithm(std::string_view name) {
  for (Algorithm a : kAlgorithms)
    if (name == algorithm_name(a)) return a;
  return std::nullopt;
}

void DetectorStats::add(const StepStats& s) {
  if (created_by_filled.size() < s.live_by_filled.size()) created_by_filled.resize(s.live_by_filled.size());
  for (size_t i = 0; i < s.live_by_filled.size(); ++i) created_by_filled[i] += s.live_by_filled[i];
  created += s.created;
  messages += s.messages;
  lost += s.lost;
  value_messages += s.value_messages;
  ++observed_steps;
  bytes += s.bytes;
  matches += s.matches;
  peak_live = std::max(peak_live, s.live);
  seconds += s.seconds;
  last = s;
  if (steps.size() < max_steps) steps.push_back(s);
  else steps_truncated = true;
}

}  // namespace dw::watch
