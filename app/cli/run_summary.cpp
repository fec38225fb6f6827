#include "app/cli/run_summary.h"

#include "sim/watch_hosting.h"

namespace dw::app {

void print_detector_stats(std::ostream& out, const watch::DetectorStats& st) {
  out << "    PatternMatchers: " << st.created << " created, peak " << st.peak_live << " live in a step";
  if (st.messages) out << ", " << st.messages << " sent (" << st.bytes << " bytes)";
  if (st.lost) out << ", " << st.lost << " lost to links gone";
  if (st.value_messages) out << "; " << st.value_messages << " messages of neighbours' values for aggregates";
  if (st.created_by_filled.size() > 1) {  // nothing when no step was observed
    out << "; by slots filled:";
    for (size_t i = 1; i < st.created_by_filled.size(); ++i) out << " " << i << ":" << st.created_by_filled[i];
  }
  out << "\n";
}

nlohmann::ordered_json stats_json(const sim::WatchSpec& spec, const watch::DetectorStats& st, uint64_t matches) {
  nlohmann::ordered_json j;
  j["name"] = spec.name;
  j["watchpoint"] = spec.text;
  j["matches"] = matches;
  j["created"] = st.created;
  j["messages"] = st.messages;
  j["bytes"] = st.bytes;
  j["peak_live"] = st.peak_live;
  j["created_by_filled"] = st.created_by_filled;
  j["lost"] = st.lost;
  if (st.value_messages) j["value_messages"] = st.value_messages;
  j["history_values"] = st.history_values;
  j["seconds"] = st.seconds;
  j["stopped"] = st.stopped;
  if (st.stopped) j["stop_reason"] = st.stop_reason;
  nlohmann::ordered_json steps = nlohmann::ordered_json::array();
  for (const watch::StepStats& s : st.steps) {
    steps.push_back({{"step", s.step},
                     {"live_by_filled", s.live_by_filled},
                     {"live", s.live},
                     {"created", s.created},
                     {"messages", s.messages},
                     {"bytes", s.bytes},
                     {"lost", s.lost},
                     {"matches", s.matches},
                     {"seconds", s.seconds}});
  }
  j["per_step"] = std::move(steps);
  if (st.steps_truncated) j["per_step_truncated"] = true;  // only the first DetectorStats::kMaxSteps
  return j;
}

void add_reading_json(nlohmann::ordered_json& entry, const sim::WatchSpec& spec) {
  entry["algorithm"] = spec.algorithm_name();
  entry["shape"] = spec.shape_name();
  if (spec.distributed()) entry["states"] = spec.states_name();
  entry["action"] = sim::action_name(spec.action);
}

void print_first_matches(std::ostream& out, std::span<const std::string> slot_names, uint64_t listed, size_t print,
                         const MatchAt& match) {
  for (size_t i = 0; i < listed && i < print; ++i) {
    const auto [t, group] = match(i);
    out << "    t=" << t << " " << group_text(slot_names, group) << "\n";
  }
  if (listed > print && print > 0) out << "    ... " << (listed - print) << " more (--matches FILE writes them all)\n";
}

bool say_stopped(std::ostream& errors, const std::string& name, const watch::DetectorStats& st, const char* budget) {
  if (st.stopped) errors << "dwatch: " << name << ": stopped: " << sim::stop_text(st.stop_reason, budget) << "\n";
  return st.stopped;
}

std::string reading_text(watch::Algorithm algorithm, const watch::DetectorOptions& options, int slots) {
  std::string s = watch::algorithm_name(algorithm);
  const watch::GroupShape shape = watch::group_shape(algorithm, options);
  const bool paper = !options.shape || *options.shape == watch::group_shape(algorithm, {});
  if (watch::simultaneous(algorithm, options)) {
    const int64_t hops = watch::hop_latency(shape, slots);
    s += ", simultaneous states, " + std::string(watch::shape_name(shape)) + " groups, latency " +
         std::to_string(hops) + " hop" + (hops == 1 ? "" : "s");
  } else if (!paper) {
    s += std::string(", ") + watch::shape_name(shape) + " groups";
  }
  return s;
}

std::string group_text(std::span<const std::string> slot_names, std::span<const watch::ModuleId> ids) {
  if (slot_names.empty()) return "(no module)";  // a zero-slot watchpoint's match (docs/design.md §4c)
  std::string s;
  for (size_t i = 0; i < ids.size(); ++i) s += (i ? " " : "") + slot_names[i] + "=" + std::to_string(ids[i]);
  return s;
}

}  // namespace dw::app
