// What `run` and `replay` say of their watchpoints: each one's statistics on the console and as
// JSON (--stats), how it reads, the first of its matches and a budget that stopped it; and a
// matched group (`render` too). The two commands' summaries are made of these.
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <ostream>
#include <span>
#include <string>
#include <utility>

#include "sim/watch_spec.h"
#include "watch/detector.h"
#include "watch/watchpoint.h"

namespace dw::app {

void print_detector_stats(std::ostream& out, const watch::DetectorStats& st);
// A watchpoint's entry of --stats: its name, text and matches, then its statistics.
nlohmann::ordered_json stats_json(const sim::WatchSpec& spec, const watch::DetectorStats& st, uint64_t matches);
// And its reading and action after them, for a run's (whose watchpoints each read their own way).
void add_reading_json(nlohmann::ordered_json& entry, const sim::WatchSpec& spec);
// The first `print` of the `listed` matches a watchpoint lists, a line each ("    t=3 a=4 b=5"),
// and how many more there are; `match(i)` is the i-th: its watch step and its group.
using MatchAt = std::function<std::pair<int64_t, std::span<const watch::ModuleId>>(size_t i)>;
void print_first_matches(std::ostream& out, std::span<const std::string> slot_names, uint64_t listed, size_t print,
                         const MatchAt& match);
// A watchpoint its budget stopped says so on `errors` (`budget`: what sets it), with the matches it
// keeps; whether it stopped.
bool say_stopped(std::ostream& errors, const std::string& name, const watch::DetectorStats& st, const char* budget);
// How a detector reads: "distributed" for the paper's readings, else with what differs, as in
// "distributed, simultaneous states, any groups, latency 6 hops".
std::string reading_text(watch::Algorithm algorithm, const watch::DetectorOptions& options, int slots);
// A matched group as "a=4 b=5 c=9": each slot's name and the module filling it.
std::string group_text(std::span<const std::string> slot_names, std::span<const watch::ModuleId> ids);

}  // namespace dw::app
