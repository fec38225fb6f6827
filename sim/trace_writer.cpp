#include <nlohmann/json.hpp>

#include "sim/output_file.h"
#include "sim/trace.h"

namespace dw::sim {

std::variant<std::vector<HostedWatchpoint>, std::string> hosted_watches(std::span<const WatchSpec> watches,
                                                                        const std::string& trace_path,
                                                                        const watch::DetectorOptions& base) {
  std::vector<WatchSpec> specs(watches.begin(), watches.end());
  for (WatchSpec& spec : specs) {
    spec.options.live_budget = base.live_budget;
    spec.options.optimizations = base.optimizations;
  }
  return compile_all(specs, trace_path);
}

TraceWriter::TraceWriter(std::ostream& out, const watch::Universe& universe,
                         std::span<const Intervention> interventions, std::span<const WatchSpec> watches)
    : out_(out), universe_(universe) {
  // Variable names are escaped once by nlohmann; the numbers are written per line.
  for (const std::string& v : universe.variables)
    keys_.push_back(nlohmann::json(v).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + ":");
  out_ << "{\"wptrace\":1";
  if (!interventions.empty()) {
    out_ << ",\"interventions\":[";
    for (size_t i = 0; i < interventions.size(); ++i)
      out_ << (i ? "," : "") << intervention_json(interventions[i], universe);
    out_ << "]";
  }
  if (!watches.empty()) {
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (const WatchSpec& w : watches) list.push_back(to_json(w));
    out_ << ",\"watches\":" << list.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  }
  out_ << "}\n";
}

void TraceWriter::write(const watch::Frame& f, const Mailbox* read) {
  // The inbox's groups: (receiver, program), so a receiver's messages are one run of them.
  const size_t programs =
      read && !read->begin.empty() ? (read->begin.size() - 1) / std::max<size_t>(1, universe_.module_count()) : 0;
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
    line_ += "]";
    if (read) {
      line_ += ",\"recv\":[";
      const Messages all = read->messages.all();
      const uint32_t from = programs ? read->begin[m * programs] : 0,
                     to = programs ? read->begin[(m + 1) * programs] : 0;
      for (uint32_t k = from; k < to; ++k) {
        const Message msg = all[k];
        line_ += (k == from ? "{\"from\":" : ",{\"from\":") + std::to_string(universe_.id(msg.from)) +
                 ",\"sent\":" + std::to_string(f.step - 1) + ",\"words\":[";
        for (uint16_t w = 0; w < msg.size; ++w) line_ += (w ? "," : "") + std::to_string(msg.words[w]);
        line_ += "]}";
      }
      line_ += "]";
    }
    line_ += "}\n";
    out_ << line_;
  }
}

void TraceWriter::write_paused(const TracePause& pause) {
  out_ << nlohmann::ordered_json{{"paused", {{"watch", pause.watch}, {"t", pause.t}}}}.dump(
              -1, ' ', false, nlohmann::json::error_handler_t::replace)
       << "\n";
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
