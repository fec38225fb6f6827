#include <nlohmann/json.hpp>

#include "sim/output_file.h"
#include "sim/trace.h"

namespace dw::sim {

std::pair<watch::Algorithm, watch::DetectorOptions> trace_watch_reading(const TraceWatch& w,
                                                                        watch::DetectorOptions base) {
  const watch::Algorithm algorithm = watch::parse_algorithm(w.algorithm).value_or(watch::Algorithm::Distributed);
  base.shape = watch::parse_shape(w.shape);
  base.states =
      algorithm == watch::Algorithm::Distributed ? watch::parse_states(w.states) : std::optional<watch::States>();
  return {algorithm, base};
}

std::variant<std::vector<HostedWatchpoint>, std::string> hosted_watches(std::span<const TraceWatch> watches,
                                                                        const std::string& trace_path,
                                                                        const watch::DetectorOptions& base) {
  std::vector<HostedWatchpoint> out;
  for (const TraceWatch& w : watches) {
    auto compiled =
        watch::compile_watchpoint(w.name, watch::SourceText(trace_path + " (watch " + w.name + ")", w.text));
    if (auto* e = std::get_if<watch::CompileError>(&compiled)) return e->format();
    const auto [algorithm, options] = trace_watch_reading(w, base);
    out.push_back({std::move(std::get<watch::Watchpoint>(compiled)), algorithm,
                   parse_action(w.action).value_or(MatchAction::Log), options});
  }
  return out;
}

std::vector<TraceWatch> trace_watches(std::span<const HostedWatchpoint> watches) {
  std::vector<TraceWatch> out;
  for (const HostedWatchpoint& h : watches)
    out.push_back({h.watchpoint.name, watch::to_string(h.watchpoint.ast),
                   std::string(watch::algorithm_name(h.algorithm)),
                   std::string(watch::shape_name(watch::group_shape(h.algorithm, h.options))),
                   std::string(watch::states_name(h.options.states.value_or(watch::States::Consistent))),
                   std::string(action_name(h.action))});
  return out;
}

TraceWriter::TraceWriter(std::ostream& out, const watch::Universe& universe,
                         std::span<const Intervention> interventions, std::span<const TraceWatch> watches)
    : out_(out), universe_(universe) {
  // Variable names are escaped once by nlohmann; the numbers are written per line.
  for (const std::string& v : universe.variables) keys_.push_back(nlohmann::json(v).dump() + ":");
  out_ << "{\"wptrace\":1";
  if (!interventions.empty()) {
    out_ << ",\"interventions\":[";
    for (size_t i = 0; i < interventions.size(); ++i)
      out_ << (i ? "," : "") << intervention_json(interventions[i], universe);
    out_ << "]";
  }
  if (!watches.empty()) {
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (const TraceWatch& w : watches)
      list.push_back({{"name", w.name},
                      {"text", w.text},
                      {"algorithm", w.algorithm},
                      {"shape", w.shape},
                      {"states", w.states},
                      {"action", w.action}});
    out_ << ",\"watches\":" << list.dump();
  }
  out_ << "}\n";
}

void TraceWriter::write(const watch::Frame& f) {
  const std::string t = std::to_string(f.step);
  for (uint32_t m = 0; m < universe_.module_count(); ++m) {
    if (!f.present[m]) continue;
    line_ = "{\"t\":" + t + ",\"m\":" + std::to_string(universe_.id(m)) + ",\"vars\":{";
    bool first = true;
    for (size_t v = 0; v < keys_.size(); ++v) {
      const size_t at = static_cast<size_t>(m) * f.variable_count + v;
      if (!f.has(at)) continue;
      line_ += (first ? "" : ",") + keys_[v] + std::to_string(f.values[at]);
      first = false;
    }
    line_ += "},\"nbrs\":[";
    first = true;
    for (uint32_t n : f.neighbors(m)) {
      line_ += (first ? "" : ",") + std::to_string(universe_.id(n));
      first = false;
    }
    line_ += "]}\n";
    out_ << line_;
  }
}

void TraceWriter::write_paused(const TracePause& pause) {
  out_ << nlohmann::ordered_json{{"paused", {{"watch", pause.watch}, {"t", pause.t}}}}.dump() << "\n";
}

std::string write_trace(const Trace& trace, const std::string& path) {
  std::string error;
  auto out = OutputFile::open(path, &error);
  if (!out) return error;
  auto made = FrameReader::make(trace, std::nullopt, default_frame_budget());
  if (auto* why = std::get_if<std::string>(&made)) return *why;
  FrameReader& frames = std::get<FrameReader>(made);
  TraceWriter writer(out->stream(), frames.universe());
  for (int64_t t = 0; t < trace.step_count(); ++t) writer.write(frames.frame(t));
  return out->commit();
}

}  // namespace dw::sim
