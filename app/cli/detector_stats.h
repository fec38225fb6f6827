// How the commands print what a detector did: its statistics on the console and as JSON
// (--stats), how it reads a watchpoint, and a matched group.
#pragma once

#include <nlohmann/json.hpp>
#include <ostream>
#include <span>
#include <string>

#include "watch/detector.h"
#include "watch/watchpoint.h"

namespace dw::app {

void print_detector_stats(std::ostream& out, const watch::DetectorStats& st);
nlohmann::ordered_json stats_json(const watch::Watchpoint& w, const watch::DetectorStats& st, uint64_t matches);
// How a detector reads: "distributed" for the paper's readings, else with what differs, as in
// "distributed, simultaneous states, any groups, latency 6 hops".
std::string reading_text(watch::Algorithm algorithm, const watch::DetectorOptions& options, int slots);
// A matched group as "a=4 b=5 c=9": each slot's name and the module filling it.
std::string group_text(std::span<const std::string> slot_names, std::span<const watch::ModuleId> ids);

}  // namespace dw::app
