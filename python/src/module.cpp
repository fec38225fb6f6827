// dwatch._dwatch: the compiled part of the Python package (python/dwatch/__init__.py re-exports it).
#include <pybind11/numpy.h>

#include <sstream>

#include "python/src/bindings.h"
#include "watch/explain.h"

namespace dw::python {

void add_check(py::module_& m) {
  m.def(
      "check",
      [](const std::string& text, const std::string& name) {
        sim::WatchSpec spec;
        spec.name = name;
        spec.text = text;
        std::ostringstream out;
        watch::explain_watchpoint(compile_or_raise(spec).watchpoint, out);
        return out.str();
      },
      py::arg("text"), py::arg("name") = "w1",
      "Parses, checks and compiles a watchpoint; returns what `dwatch check` prints for it (normal form, slots, "
      "E+, offsets, spans, the PatternMatcher's size), or raises WatchError.");
}

}  // namespace dw::python

PYBIND11_MODULE(_dwatch, m) {
  m.doc() = "Distributed watchpoints over modular-robot ensembles: check, replay, and the debugging Session.";
  m.attr("__version__") = DWATCH_VERSION;
  dw::python::add_errors(m);
  dw::python::add_check(m);
  dw::python::add_replay(m);
  dw::python::add_session(m);
  dw::python::add_python_programs(m);
  // pybind11 (2.10, Debian's) looks numpy's C API up into a function-local static the first time
  // an array is made. Two threads making their first arrays at once deadlocked: one waited on
  // that static holding the GIL, the other needed the GIL to finish it. Made here, at import,
  // while one thread holds the GIL.
  [[maybe_unused]] const pybind11::array_t<int64_t> numpy_api_looked_up(0);
}
