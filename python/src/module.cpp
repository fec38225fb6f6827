// dwatch._dwatch: the compiled part of the Python package (python/dwatch/__init__.py re-exports it).
#include "python/src/bindings.h"

PYBIND11_MODULE(_dwatch, m) {
  m.doc() = "Distributed watchpoints over modular-robot ensembles: check, replay, and the debugging Session.";
  m.attr("__version__") = DWATCH_VERSION;
  dw::python::add_errors(m);
  dw::python::add_check(m);
  dw::python::add_replay(m);
  dw::python::add_session(m);
}
