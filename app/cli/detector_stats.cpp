#include "app/cli/detector_stats.h"

#include "watch/ast.h"

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

nlohmann::ordered_json stats_json(const watch::Watchpoint& w, const watch::DetectorStats& st, uint64_t matches) {
  nlohmann::ordered_json j;
  j["name"] = w.name;
  j["watchpoint"] = watch::to_string(w.ast);
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
  std::string s;
  for (size_t i = 0; i < ids.size(); ++i) s += (i ? " " : "") + slot_names[i] + "=" + std::to_string(ids[i]);
  return s;
}

}  // namespace dw::app
