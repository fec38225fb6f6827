// dwatch.replay: watchpoints over a trace file or over columns held in numpy arrays, through the
// loop `dwatch replay` runs (sim/replay.h).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <chrono>
#include <optional>

#include "python/src/bindings.h"
#include "python/src/matches.h"
#include "sim/replay.h"
#include "sim/run_outputs.h"
#include "sim/trace.h"

namespace dw::python {
namespace {

sim::Trace trace_from_file(const std::string& path) {
  raise_if_missing(path);
  std::variant<sim::Trace, std::vector<sim::TraceError>> read;
  {
    py::gil_scoped_release released;
    read = sim::read_trace(path);
  }
  if (auto* errors = std::get_if<std::vector<sim::TraceError>>(&read)) {
    std::string message;
    for (const sim::TraceError& e : *errors) message += (message.empty() ? "" : "\n") + e.format();
    const sim::TraceError& first = errors->front();
    raise_error_at("TraceError", message, first.file, first.line, first.column);
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
  const std::string trace_name =
      columns ? "<columns>" : py::module_::import("os").attr("fspath")(trace_arg).cast<std::string>();
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
  // Ctrl-C: Python's handlers run in the main thread holding the GIL, so the loop looks for a
  // pending signal now and then (a few times a second) and unwinds out of the replay.
  struct Interrupted {};
  auto next_look = std::chrono::steady_clock::now();
  const auto look_for_signals = [&](int64_t) {
    const auto now = std::chrono::steady_clock::now();
    if (now < next_look) return;
    next_look = now + std::chrono::milliseconds(50);
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw Interrupted{};
  };
  try {
    py::gil_scoped_release released;
    stats = sim::replay(
        std::get<sim::FrameReader>(made), trace.step_count(), watched,
        [&](size_t w, int64_t detected, int64_t t, std::span<const watch::ModuleId> ids,
            std::span<const watch::Value>) {
          found[w].add(detected, t, ids, watched[w].watchpoint.program.slot_names.size());
        },
        look_for_signals, sim::RunOutputs::replay_drains(trace, watches.is_none()));
  } catch (const Interrupted&) {
    throw py::error_already_set();  // the signal handler's exception (KeyboardInterrupt), still set
  }
  py::dict out;
  for (size_t i = 0; i < watched.size(); ++i) {
    const watch::Watchpoint& w = watched[i].watchpoint;
    out[py::str(w.name)] = Matches::make(w.name, w.program.slot_names, std::move(found[i]));
  }
  // A watchpoint past its budget stops; the others go on, and what every one found is kept, as
  // the command line prints it: the exception carries them.
  py::dict stopped;
  std::string message;
  for (size_t i = 0; i < watched.size(); ++i)
    if (stats[i].stopped) {
      const std::string& name = watched[i].watchpoint.name;
      stopped[py::str(name)] = stats[i].stop_reason;
      message += (message.empty() ? "" : "\n") + name + ": stopped: " + stats[i].stop_reason;
    }
  if (!stopped.empty()) {
    const py::object type = py::module_::import("dwatch._dwatch").attr("BudgetError");
    py::object e = type(message + " (max_live= sets the budget)");
    e.attr("matches") = out;
    e.attr("stopped") = stopped;
    PyErr_SetObject(type.ptr(), e.ptr());
    throw py::error_already_set();
  }
  return out;
}

}  // namespace

sim::WatchSpec reading(const std::string& algorithm, const std::optional<std::string>& shape,
                       const std::optional<std::string>& states, uint64_t max_live) {
  sim::WatchSpec r;
  if (!sim::read_word(r, algorithm, sim::WatchWord::Algorithm))
    raise_error("ArgumentError", "algorithm must be 'centralized' or 'distributed', not '" + algorithm + "'");
  r.options.live_budget = max_live;
  if (shape && !sim::read_word(r, *shape, sim::WatchWord::Shape))
    raise_error("ArgumentError", "shape must be 'chain', 'ordered' or 'any', not '" + *shape + "'");
  if (states && !sim::read_word(r, *states, sim::WatchWord::States))
    raise_error("ArgumentError", "states must be 'consistent' or 'simultaneous', not '" + *states + "'");
  if (const std::string why = watch::unsupported(r.algorithm, r.options); !why.empty())
    raise_error("ArgumentError", why);
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
  Every column holds integers (numpy integer arrays, or sequences of ints), checked as a file's
  numbers are: a float, a bool, a string or a value beyond int64 is a TraceError naming the column
  and the line (counted from 0), as is a key other than these.
watches: a watchpoint's text, a sequence of texts (named w1, w2, ...), or {name: text}; None: the
  watchpoints the trace's header lists.
algorithm, shape, states, max_live: as --algorithm, --shape, --states and --max-live.
count_only: count the matches (Matches.count) and keep none, as `dwatch replay` without
  --matches does: for traces with millions of matches.
Raises WatchError, TraceError, Error (a reading that cannot run), or BudgetError when a
watchpoint exceeds max_live: it stops, the others go on, and the exception's matches holds every
watchpoint's {name: Matches} (the stopped one's up to its stop) and stopped {name: reason}.
Ctrl-C stops a replay between steps and raises KeyboardInterrupt.)");
}

}  // namespace dw::python
