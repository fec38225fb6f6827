// The Python package's module, dwatch._dwatch: each file adds one part of it.
#pragma once

#include <pybind11/pybind11.h>

#include <cstdint>
#include <optional>
#include <string>

#include "scenarios/scenario.h"
#include "sim/trace.h"
#include "sim/watch_spec.h"
#include "watch/detector.h"
#include "watch/watchpoint.h"

namespace dw::python {

namespace py = pybind11;

// dwatch.Error and its subclasses, made in the module (errors.cpp).
void add_errors(py::module_& m);
// Raises dwatch.<kind> (Error, ScenarioError, TraceError, CommandError) with `message`.
[[noreturn]] void raise_error(const char* kind, const std::string& message);
// The same with where the (first) mistake is: its file, line and column (1-based), the
// attributes every dwatch error has (None when not known).
[[noreturn]] void raise_error_at(const char* kind, const std::string& message, const std::string& file, uint64_t line,
                                 uint64_t column);
// ScenarioError with the place of the first "file:line:col: error: " line of `message`.
[[noreturn]] void raise_scenario_error(const std::string& message);
// FileNotFoundError (errno ENOENT) for `path`, unless the file exists.
void raise_if_missing(const std::string& path);
// Raises dwatch.WatchError for a watchpoint that does not compile: line, column and message of the
// first mistake, and the caret text of all of them.
[[noreturn]] void raise_watch_error(const watch::CompileError& error);
// The watchpoint `spec` compiled (its source named "<watch NAME>"), or dwatch.WatchError.
sim::HostedWatchpoint compile_or_raise(const sim::WatchSpec& spec);

// A watchpoint's reading (its name and text left empty) from the names `--algorithm`, `--shape`
// and `--states` take, with the `--max-live` budget; dwatch.Error when a name is wrong or the
// reading cannot run.
sim::WatchSpec reading(const std::string& algorithm, const std::optional<std::string>& shape,
                       const std::optional<std::string>& states, uint64_t max_live);

// The trace of dwatch.replay's columns (a dict: "t", "m", the neighbours as "nbr_begin" + flat
// "nbrs" or as "nbrs" alone, one sequence per line, and "vars", name -> values), each checked as
// strictly as a trace file's numbers; dwatch.TraceError naming the column and the line (columns.cpp).
sim::Trace trace_from_columns(const py::dict& columns);

void add_check(py::module_& m);    // dwatch.check (module.cpp)
void add_replay(py::module_& m);   // dwatch.replay and dwatch.Matches
void add_session(py::module_& m);  // dwatch.Session

// The host programs written in Python that Session(programs=) gives, by name: each a class (made
// once per session) or an instance with `vars`, `params` and step(m) (python_program.cpp).
scenarios::ProvidedPrograms python_programs(const std::optional<py::dict>& programs);
void add_python_programs(py::module_& m);  // dwatch.Module, step(m)'s m

}  // namespace dw::python
