// dwatch.replay: watchpoints over a trace file or over columns held in numpy arrays, through the
// loop `dwatch replay` runs (sim/replay.h).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <optional>

#include "python/src/bindings.h"
#include "python/src/matches.h"
#include "sim/replay.h"
#include "sim/run_outputs.h"
#include "sim/trace.h"

namespace dw::python {
namespace {

using Column = py::array_t<int64_t, py::array::c_style | py::array::forcecast>;

// The trace's lines from a mapping of columns: "t", "m", the neighbours as "nbr_begin" + "nbrs"
// (offsets and ids, flat) or as "nbrs" alone (one sequence per line), and "vars" (name -> values).
sim::Trace trace_from_columns(const py::dict& columns) {
  for (const char* key : {"t", "m", "nbrs"})
    if (!columns.contains(key)) raise_error("TraceError", std::string("the columns lack \"") + key + "\"");
  const Column t = Column::ensure(columns["t"]), m = Column::ensure(columns["m"]);
  if (!t || !m || t.ndim() != 1 || m.ndim() != 1)
    raise_error("TraceError", "\"t\" and \"m\" must be one-dimensional arrays of integers");
  Column nbr_begin, nbrs;
  if (columns.contains("nbr_begin")) {
    nbr_begin = Column::ensure(columns["nbr_begin"]);
    nbrs = Column::ensure(columns["nbrs"]);
    if (!nbr_begin || !nbrs || nbr_begin.ndim() != 1 || nbrs.ndim() != 1)
      raise_error("TraceError", "\"nbr_begin\" and \"nbrs\" must be one-dimensional arrays of integers");
  } else {  // a sequence per line: flattened here (per-line Python work: the flat form is faster)
    std::vector<int64_t> begin{0}, flat;
    for (const py::handle line : columns["nbrs"]) {
      for (const py::handle n : line) flat.push_back(n.cast<int64_t>());
      begin.push_back(static_cast<int64_t>(flat.size()));
    }
    nbr_begin = Column(static_cast<py::ssize_t>(begin.size()), begin.data());
    nbrs = Column(static_cast<py::ssize_t>(flat.size()), flat.data());
  }
  sim::Trace::Columns c;
  std::vector<Column> held;  // the value arrays, alive while their spans are read
  if (columns.contains("vars"))
    for (const auto& [name, values] : columns["vars"].cast<py::dict>()) {
      held.push_back(Column::ensure(values));
      if (!held.back() || held.back().ndim() != 1)
        raise_error("TraceError", "variable '" + name.cast<std::string>() + "' must be a one-dimensional array");
      c.variables.push_back(name.cast<std::string>());
    }
  const auto span = [](const Column& a) { return std::span<const int64_t>(a.data(), static_cast<size_t>(a.size())); };
  c.t = span(t), c.m = span(m), c.nbr_begin = span(nbr_begin), c.nbrs = span(nbrs);
  for (const Column& v : held) c.values.push_back(span(v));
  std::variant<sim::Trace, std::string> built;
  {
    py::gil_scoped_release released;
    built = sim::Trace::from_columns(c);
  }
  if (auto* error = std::get_if<std::string>(&built)) raise_error("TraceError", "the columns: " + *error);
  return std::get<sim::Trace>(std::move(built));
}

sim::Trace trace_from_file(const std::string& path) {
  std::variant<sim::Trace, std::vector<sim::TraceError>> read;
  {
    py::gil_scoped_release released;
    read = sim::read_trace(path);
  }
  if (auto* errors = std::get_if<std::vector<sim::TraceError>>(&read)) {
    std::string message;
    for (const sim::TraceError& e : *errors) message += (message.empty() ? "" : "\n") + e.format();
    raise_error("TraceError", message);
  }
  return std::get<sim::Trace>(std::move(read));
}

// The watchpoints: a text, a sequence of texts (named w1, w2, ... as on the command line) or a
// mapping of names to texts; none: those the trace's header lists, each with its run's reading.
std::vector<sim::HostedWatchpoint> hosted(const py::object& watches, const sim::WatchSpec& r, const sim::Trace& trace,
                                          const std::string& trace_name) {
  std::vector<sim::HostedWatchpoint> out;
  const auto add = [&](const std::string& name, const std::string& text) {
    sim::WatchSpec spec = r;
    spec.name = name;
    spec.text = text;
    out.push_back(compile_or_raise(spec));
  };
  if (watches.is_none()) {
    auto from_header = sim::hosted_watches(trace.watches(), trace_name, r.options);
    if (auto* errors = std::get_if<std::string>(&from_header)) raise_error("TraceError", *errors);
    out = std::get<std::vector<sim::HostedWatchpoint>>(std::move(from_header));
    if (out.empty())
      raise_error("Error", trace_name + ": the trace's header lists no watchpoints: give them with watches=");
    for (sim::HostedWatchpoint& h : out) h.action = sim::MatchAction::Log;  // every match is returned
  } else if (py::isinstance<py::str>(watches)) {
    add("w1", watches.cast<std::string>());
  } else if (py::isinstance<py::dict>(watches)) {
    for (const auto& [name, text] : watches.cast<py::dict>()) add(name.cast<std::string>(), text.cast<std::string>());
  } else {
    for (const py::handle text : watches) add("w" + std::to_string(out.size() + 1), text.cast<std::string>());
  }
  if (out.empty()) raise_error("Error", "no watchpoints to replay");
  return out;
}

py::dict replay(const py::object& trace_arg, const py::object& watches, const std::string& algorithm,
                const std::optional<std::string>& shape, const std::optional<std::string>& states, uint64_t max_live,
                bool count_only) {
  const sim::WatchSpec r = reading(algorithm, shape, states, max_live);
  const bool columns = py::isinstance<py::dict>(trace_arg);
  const std::string trace_name = columns ? "<columns>" : py::str(trace_arg).cast<std::string>();
  const sim::Trace trace = columns ? trace_from_columns(trace_arg.cast<py::dict>()) : trace_from_file(trace_name);
  const std::vector<sim::HostedWatchpoint> watched = hosted(watches, r, trace, trace_name);
  if (std::string why = sim::replay_work_problem(trace); !why.empty())
    raise_error("TraceError", trace_name + ": " + why);

  // A variable no line has reads as unknown everywhere: said, as the command line says it.
  const auto& known = trace.universe().variables;
  for (const sim::HostedWatchpoint& h : watched)
    for (const std::string& v : h.watchpoint.program.variables)
      if (std::find(known.begin(), known.end(), v) == known.end())
        py::module_::import("warnings")
            .attr("warn")("watchpoint \"" + h.watchpoint.name + "\" reads '" + v + "', which no line of " + trace_name +
                          " has: it can never match");

  auto made = sim::FrameReader::make(trace, sim::read_variables(watched), sim::default_frame_budget());
  if (auto* why = std::get_if<std::string>(&made)) raise_error("Error", trace_name + ": " + *why);
  std::vector<Matches::Builder> found(watched.size());
  for (Matches::Builder& b : found) b.keep = !count_only;
  std::vector<watch::DetectorStats> stats;
  {
    py::gil_scoped_release released;
    stats = sim::replay(
        std::get<sim::FrameReader>(made), trace.step_count(), watched,
        [&](size_t w, int64_t detected, int64_t t, std::span<const watch::ModuleId> ids,
            std::span<const watch::Value>) {
          found[w].add(detected, t, ids, watched[w].watchpoint.program.slot_names.size());
        },
        {}, sim::RunOutputs::replay_drains(trace, watches.is_none()));
  }
  for (size_t i = 0; i < watched.size(); ++i)
    if (stats[i].stopped)
      raise_error("Error",
                  watched[i].watchpoint.name + ": stopped: " + stats[i].stop_reason + " (max_live= sets the budget)");
  py::dict out;
  for (size_t i = 0; i < watched.size(); ++i) {
    const watch::Watchpoint& w = watched[i].watchpoint;
    out[py::str(w.name)] = Matches::make(w.name, w.program.slot_names, std::move(found[i]));
  }
  return out;
}

}  // namespace

sim::WatchSpec reading(const std::string& algorithm, const std::optional<std::string>& shape,
                       const std::optional<std::string>& states, uint64_t max_live) {
  sim::WatchSpec r;
  if (!sim::read_word(r, algorithm, sim::WatchWord::Algorithm))
    raise_error("Error", "algorithm must be 'centralized' or 'distributed', not '" + algorithm + "'");
  r.options.live_budget = max_live;
  if (shape && !sim::read_word(r, *shape, sim::WatchWord::Shape))
    raise_error("Error", "shape must be 'chain', 'ordered' or 'any', not '" + *shape + "'");
  if (states && !sim::read_word(r, *states, sim::WatchWord::States))
    raise_error("Error", "states must be 'consistent' or 'simultaneous', not '" + *states + "'");
  if (const std::string why = watch::unsupported(r.algorithm, r.options); !why.empty()) raise_error("Error", why);
  return r;
}

void add_replay(py::module_& m) {
  add_matches(m);
  m.def("replay", &replay, py::arg("trace"), py::arg("watches") = py::none(), py::arg("algorithm") = "distributed",
        py::arg("shape") = py::none(), py::arg("states") = py::none(), py::arg("max_live") = sim::kDefaultMatchBudget,
        py::arg("count_only") = false,
        R"(Runs watchpoints over a trace, as `dwatch replay` does; returns {name: Matches}.

trace: a wptrace v1 file's path, or columns: a dict with "t" and "m" (one entry per line: the
  step and the module), the neighbours as "nbr_begin" (lines + 1 offsets) and "nbrs" (the ids,
  flat), or as "nbrs" alone (a sequence per line, slower), and "vars" (name -> one value per line).
  Every column is converted to int64.
watches: a watchpoint's text, a sequence of texts (named w1, w2, ...), or {name: text}; None: the
  watchpoints the trace's header lists.
algorithm, shape, states, max_live: as --algorithm, --shape, --states and --max-live.
count_only: count the matches (Matches.count) and keep none, as `dwatch replay` without
  --matches does: for traces with millions of matches.
Raises WatchError, TraceError, or Error (a reading that cannot run, the budget exceeded).)");
}

}  // namespace dw::python
