// The command-line flags every detector-running command shares (`run`, `replay`, `bench`): the
// algorithm, the group shape and state mode (docs/design.md §4a), the optimization switches and
// the PatternMatcher budget, and the detector options they make.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>

#include "sim/watch_spec.h"
#include "watch/detector.h"

namespace dw::shell {

struct DetectorFlags {
  std::string algorithm_name = "distributed";
  bool no_early_termination = false;
  bool no_neighbor_culling = false;
  bool no_temporal_spans = false;
  uint64_t max_live = sim::kDefaultMatchBudget;
  std::string shape_name;   // empty: the algorithm's own
  std::string states_name;  // empty: consistent

  // The reading they give every watchpoint of the command (its name, text and action left as
  // WatchSpec has them), and its detector options.
  sim::WatchSpec reading() const;
  watch::DetectorOptions options() const { return reading().options; }
};

// --algorithm (unless the command picks algorithms its own way), --shape and --states
// (docs/design.md §4a), the optimization switches and the --max-live budget.
void add_detector_flags(CLI::App& cmd, DetectorFlags& flags, bool with_algorithm = true);

}  // namespace dw::shell
