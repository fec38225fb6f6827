// Command-line flags every detector-running command shares, and how detector statistics print.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <ostream>
#include <span>
#include <string>

#include "watch/detector.h"
#include "watch/watchpoint.h"

namespace dw::app {

struct DetectorFlags {
  std::string algorithm_name = "distributed";
  watch::Algorithm algorithm() const;
  bool no_early_termination = false;
  bool no_neighbor_culling = false;
  bool no_temporal_spans = false;
  uint64_t max_live = 20'000'000;
  std::string shape_name;   // empty: the algorithm's own
  std::string states_name;  // empty: consistent

  watch::DetectorOptions options() const;
};

// --algorithm (unless the command picks algorithms its own way), --shape and --states
// (docs/design.md §4a), the optimization switches and the --max-live budget.
void add_detector_flags(CLI::App& cmd, DetectorFlags& flags, bool with_algorithm = true);
void print_detector_stats(std::ostream& out, const watch::DetectorStats& st);
nlohmann::ordered_json stats_json(const watch::Watchpoint& w, const watch::DetectorStats& st, uint64_t matches);
// A matched group as "a=4 b=5 c=9": each slot's name and the module filling it.
// How a detector reads: "distributed" for the paper's readings, else with what differs, as in
// "distributed, simultaneous states, any groups, latency 6 hops".
std::string reading_text(watch::Algorithm algorithm, const watch::DetectorOptions& options, int slots);
std::string group_text(std::span<const std::string> slot_names, std::span<const watch::ModuleId> ids);

}  // namespace dw::app
