// A window of history read from a trace's lines (sim/trace_history.h): dense frames for the
// values, presence and neighbours, and each line's "recv" for the messages read.
#include "sim/trace_history.h"

#include <algorithm>

namespace dw::sim {

int64_t trace_origin(const Trace& trace, uint32_t m, uint32_t var, int64_t t) {
  const auto value_at = [&](int64_t s) -> std::optional<int64_t> {
    const auto line = trace.line_of(s, m);
    if (!line) return std::nullopt;
    return trace.value(*line, var).value_or(0);
  };
  for (int64_t w = t; w > 0; --w) {
    const auto now = value_at(w), before = value_at(w - 1);
    if (now && (!before || *now != *before)) return w;
  }
  return 0;
}

std::variant<CausalHistory, std::string> trace_window(const Trace& trace, int64_t first, int64_t last) {
  auto made = FrameReader::make(trace, std::nullopt, default_frame_budget());
  if (auto* why = std::get_if<std::string>(&made)) return *why;
  FrameReader& frames = std::get<FrameReader>(made);
  CausalHistory h;
  h.modules = trace.universe().module_count();
  h.variables = static_cast<uint32_t>(frames.universe().variables.size());
  h.first = first;
  const auto values_of = [&](const watch::Frame& f) {
    std::vector<int64_t> values(f.values.begin(), f.values.end());
    for (size_t i = 0; i < values.size(); ++i)
      if (!f.has(i)) values[i] = 0;
    return values;
  };
  h.before = first > 0 ? values_of(frames.frame(first - 1)) : std::vector<int64_t>(size_t{h.modules} * h.variables, 0);
  for (int64_t s = first; s <= last; ++s) {
    const watch::Frame f = frames.frame(s);
    StepRecord rec;
    rec.step = s;
    // The writes the header's interventions made at the start of s (the frames hold their effect).
    for (const TraceIntervention& i : trace.interventions()) {
      if (i.at != s) continue;
      const watch::Universe& u = frames.universe();
      uint32_t dense = i.module;  // ids ascending, or each id its index
      if (!u.module_ids.empty()) {
        const auto at = std::lower_bound(u.module_ids.begin(), u.module_ids.end(), i.module);
        dense = at != u.module_ids.end() && *at == i.module ? static_cast<uint32_t>(at - u.module_ids.begin())
                                                            : u.module_count();
      }
      if (dense >= u.module_count()) continue;  // no line names it
      const auto variable = std::find(u.variables.begin(), u.variables.end(), i.variable);
      rec.outside.push_back(
          {.by = i.scheduled ? OutsideWrite::By::Event : OutsideWrite::By::Intervention,
           .module = dense,
           .column = variable == u.variables.end() ? -1 : static_cast<int>(variable - u.variables.begin()),
           .value = i.value,
           .remove = i.remove});
    }
    rec.values = values_of(f);
    rec.present.assign(f.present.begin(), f.present.end());
    auto graph = std::make_shared<NeighborGraph>();
    graph->begin.assign(f.nbr_begin.begin(), f.nbr_begin.end());
    graph->ids.assign(f.nbrs.begin(), f.nbrs.end());
    rec.graph = std::move(graph);
    const auto [begin, end] = trace.lines_at(s);
    for (uint64_t line = begin; line < end; ++line)
      for (const Trace::Read& r : trace.received(line)) {
        rec.read.push_back({r.from, trace.line_module(line), r.sent, static_cast<uint32_t>(rec.words.size()),
                            static_cast<uint32_t>(r.words.size())});
        rec.words.insert(rec.words.end(), r.words.begin(), r.words.end());
      }
    rec.index_reads(h.modules);
    h.steps.push_back(std::move(rec));
  }
  return h;
}

std::variant<Cone, std::string> why_in_trace(const Trace& trace, uint64_t module, const std::string& variable,
                                             int64_t t, int depth, bool narrow) {
  if (!trace.has_messages())
    return "the trace says nothing of messages (no line has \"recv\": record it with `dwatch run --record "
           "--record-messages`)";
  const watch::Universe& universe = trace.universe();
  uint32_t m = 0;
  while (m < universe.module_count() && universe.id(m) != module) ++m;
  if (m == universe.module_count()) return "no module " + std::to_string(module) + " in the trace";
  const auto var = std::find(universe.variables.begin(), universe.variables.end(), variable);
  if (var == universe.variables.end()) return "no variable '" + variable + "' in the trace";
  if (t >= trace.step_count())
    return "step " + std::to_string(t) + " is past the trace's last, " + std::to_string(trace.step_count() - 1);
  if (!trace.line_of(t, m)) return "module " + std::to_string(module) + " has no line at step " + std::to_string(t);
  const auto column = static_cast<uint32_t>(var - universe.variables.begin());
  const ValueAsked value{m, static_cast<int>(column), t, trace_origin(trace, m, column, t)};
  auto window = trace_window(trace, window_start({&value, 1}, depth), value.origin);
  if (auto* why = std::get_if<std::string>(&window)) return std::move(*why);
  return cone_of(std::get<CausalHistory>(window), {&value, 1}, depth, narrow);
}

}  // namespace dw::sim
