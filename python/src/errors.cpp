#include <Python.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <regex>

#include "python/src/bindings.h"

namespace dw::python {
namespace {

py::object error_type(const char* kind) { return py::module_::import("dwatch._dwatch").attr(kind); }

// A new exception class of the module, deriving from `bases`.
void add_error(py::module_& m, const char* name, py::object bases, const char* doc) {
  const std::string qualified = std::string("dwatch.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr);
  if (!type) throw py::error_already_set();
  m.attr(name) = py::reinterpret_steal<py::object>(type);
}

}  // namespace

void add_errors(py::module_& m) {
  add_error(m, "Error", py::reinterpret_borrow<py::object>(PyExc_Exception),
            "What dwatch refuses or fails to do; its message is the command line's.");
  const py::object error = m.attr("Error");
  // Where the mistake is, on every dwatch error: None unless the error says.
  for (const char* where : {"file", "line", "column"}) error.attr(where) = py::none();
  const py::object value_error = py::reinterpret_borrow<py::object>(PyExc_ValueError);
  add_error(m, "WatchError", py::make_tuple(error, value_error),
            "A watchpoint with mistakes. line, column (1-based) and message: the first mistake; "
            "text: every mistake with the source line and a caret under the spot, as `dwatch check` prints them.");
  add_error(m, "ScenarioError", py::make_tuple(error, value_error),
            "A scenario file that cannot be loaded; the message lists its mistakes as file:line:col: error: ...");
  add_error(m, "TraceError", py::make_tuple(error, value_error),
            "A trace (a file or columns) with mistakes; the message lists them as the command line does.");
  add_error(m, "ArgumentError", py::make_tuple(error, value_error),
            "An argument out of its range or not one of its words (threads=0, algorithm='magic', a camera that "
            "sees nothing).");
  add_error(m, "BudgetError", error,
            "A watchpoint exceeded its live-match budget (max_live) and stopped. matches: every watchpoint's "
            "{name: Matches}, the stopped ones' up to their stop; stopped: {name: reason}.");
  add_error(m, "CommandError", error,
            "A session command that is wrong or failed; the message is what `dwatch session` says.");
}

void raise_error(const char* kind, const std::string& message) {
  PyErr_SetObject(error_type(kind).ptr(), py::str(message).ptr());
  throw py::error_already_set();
}

void raise_error_at(const char* kind, const std::string& message, const std::string& file, uint64_t line,
                    uint64_t column) {
  py::object e = error_type(kind)(message);
  e.attr("file") = file;
  e.attr("line") = line;
  e.attr("column") = column;
  PyErr_SetObject(error_type(kind).ptr(), e.ptr());
  throw py::error_already_set();
}

void raise_scenario_error(const std::string& message) {
  static const std::regex place(R"(^(.*?):(\d+):(\d+): error: )");
  std::smatch at;
  const std::string first = message.substr(0, message.find('\n'));
  if (!std::regex_search(first, at, place)) raise_error("ScenarioError", message);
  raise_error_at("ScenarioError", message, at[1].str(), std::stoull(at[2].str()), std::stoull(at[3].str()));
}

void raise_if_missing(const std::string& path) {
  std::error_code error;
  if (std::filesystem::exists(path, error) || error) return;  // other problems: the reader's words
  PyErr_SetObject(PyExc_FileNotFoundError, py::make_tuple(ENOENT, std::strerror(ENOENT), path).ptr());
  throw py::error_already_set();
}

void raise_watch_error(const watch::CompileError& error) {
  const std::string text = error.format();
  const watch::Diagnostic& first = error.diagnostics.front();
  const watch::Location at = error.source->locate(first.span.begin);
  py::object e = error_type("WatchError")(text);
  e.attr("file") = error.source->name();
  e.attr("line") = at.line;
  e.attr("column") = at.column;
  e.attr("message") = first.message;
  e.attr("text") = text;
  PyErr_SetObject(error_type("WatchError").ptr(), e.ptr());
  throw py::error_already_set();
}

sim::HostedWatchpoint compile_or_raise(const sim::WatchSpec& spec) {
  auto compiled = sim::compile(spec, watch::SourceText("<watch " + spec.name + ">", spec.text));
  if (auto* error = std::get_if<watch::CompileError>(&compiled)) raise_watch_error(*error);
  return std::get<sim::HostedWatchpoint>(std::move(compiled));
}

}  // namespace dw::python
