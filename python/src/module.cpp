// dwatch._dwatch: the compiled part of the Python package (python/dwatch/__init__.py re-exports it).
#include <sstream>

#include "app/explain.h"
#include "python/src/bindings.h"

namespace dw::python {

void add_check(py::module_& m) {
  m.def(
      "check",
      [](const std::string& text, const std::string& name) {
        const watch::Watchpoint w = compile_or_raise(name, text);
        std::ostringstream out;
        app::explain_watchpoint(w, out);
        return out.str();
      },
      py::arg("text"), py::arg("name") = "w",
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
}
