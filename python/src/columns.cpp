// A trace from columns held in Python (numpy arrays or sequences), for dwatch.replay: each column
// checked as strictly as a trace file's numbers are read (integers only, within int64; no floats,
// booleans or strings), with the column and the line in the error, and then handed to
// sim::Trace::from_columns, which checks the lines as the file reader does.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "python/src/bindings.h"

namespace dw::python {
namespace {

using Column = py::array_t<int64_t, py::array::c_style | py::array::forcecast>;

[[noreturn]] void refuse(size_t line, const std::string& what, const std::string& problem) {
  raise_error("TraceError", "the columns: line " + std::to_string(line) + ": " + what + " " + problem);
}

std::string shown(const py::handle item) { return py::repr(item).cast<std::string>(); }

// One Python number of a column: an int (or numpy integer), never a bool, a float or a string.
int64_t integer_item(const py::handle item, size_t line, const std::string& what) {
  const py::object numpy_bool = py::module_::import("numpy").attr("bool_");
  if (PyBool_Check(item.ptr()) || py::isinstance(item, numpy_bool) || !PyIndex_Check(item.ptr()))
    refuse(line, what, "must be an integer, not " + shown(item));
  const py::object index = py::reinterpret_steal<py::object>(PyNumber_Index(item.ptr()));
  if (!index) throw py::error_already_set();
  int overflow = 0;
  const long long value = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
  if (overflow != 0) refuse(line, what, "does not fit in a signed 64-bit integer: " + shown(item));
  if (value == -1 && PyErr_Occurred()) throw py::error_already_set();
  return value;
}

// A column as int64; `what` names it in errors ("step \"t\"", "variable 'x'").
Column integer_column(const py::handle value, const std::string& what) {
  py::array a;
  try {
    // A sequence is read item by item (numpy would make [1, 2**63] float64, losing the 1's exactness).
    const py::module_ numpy = py::module_::import("numpy");
    a = py::isinstance<py::array>(value) ? numpy.attr("asarray")(value)
                                         : numpy.attr("asarray")(value, py::arg("dtype") = "object");
  } catch (const py::error_already_set&) {  // a ragged sequence, or something numpy cannot read
    raise_error("TraceError", "the columns: " + what + " must be a one-dimensional array of integers");
  }
  if (a.ndim() != 1) raise_error("TraceError", "the columns: " + what + " must be a one-dimensional array of integers");
  const auto n = static_cast<size_t>(a.size());
  if (n == 0) return Column(0);  // numpy makes [] float64
  const char kind = a.dtype().kind();
  if (kind == 'i') return Column::ensure(a);
  if (kind == 'u') {
    const auto wide = py::array_t<uint64_t, py::array::c_style | py::array::forcecast>::ensure(a);
    for (size_t i = 0; i < n; ++i)
      if (wide.data()[i] > uint64_t{std::numeric_limits<int64_t>::max()})
        refuse(i, what, "does not fit in a signed 64-bit integer: " + std::to_string(wide.data()[i]));
    return Column::ensure(a);
  }
  if (kind == 'O') {  // Python ints beyond int64, or mixed objects
    Column out(static_cast<py::ssize_t>(n));
    const py::object item = a.attr("item");
    for (size_t i = 0; i < n; ++i) out.mutable_data()[i] = integer_item(item(i), i, what);
    return out;
  }
  // floats, booleans, strings: refused as a file's 1.0, true and "1" are
  refuse(0, what,
         "must be an integer, not " + shown(a.attr("item")(0)) + " (a " + py::str(a.dtype()).cast<std::string>() +
             " column)");
}

std::string key_name(const py::handle key) {
  if (!py::isinstance<py::str>(key)) raise_error("TraceError", "the columns' keys must be strings, not " + shown(key));
  return key.cast<std::string>();
}

}  // namespace

sim::Trace trace_from_columns(const py::dict& columns) {
  const std::set<std::string> known{"t", "m", "nbr_begin", "nbrs", "vars"};
  for (const auto& [key, value] : columns)
    if (!known.count(key_name(key)))
      raise_error("TraceError",
                  "the columns: unknown key '" + key_name(key) + "' (the keys are t, m, nbr_begin, nbrs and vars)");
  for (const char* key : {"t", "m", "nbrs"})
    if (!columns.contains(key)) raise_error("TraceError", std::string("the columns lack \"") + key + "\"");
  const Column t = integer_column(columns["t"], "step \"t\""), m = integer_column(columns["m"], "module id \"m\"");
  Column nbr_begin, nbrs;
  if (columns.contains("nbr_begin")) {
    nbr_begin = integer_column(columns["nbr_begin"], "the neighbour offsets \"nbr_begin\"");
    nbrs = integer_column(columns["nbrs"], "neighbour id \"nbrs\"");
  } else {  // a sequence per line: flattened here (per-line Python work: the flat form is faster)
    std::vector<int64_t> begin{0}, flat;
    for (const py::handle line : columns["nbrs"]) {
      if (py::isinstance<py::str>(line) || !py::isinstance<py::iterable>(line))
        refuse(begin.size() - 1, "\"nbrs\"", "must be a sequence of neighbour ids, not " + shown(line));
      for (const py::handle n : line) flat.push_back(integer_item(n, begin.size() - 1, "neighbour id \"nbrs\""));
      begin.push_back(static_cast<int64_t>(flat.size()));
    }
    nbr_begin = Column(static_cast<py::ssize_t>(begin.size()), begin.data());
    nbrs = Column(static_cast<py::ssize_t>(flat.size()), flat.data());
  }
  sim::Trace::Columns c;
  std::vector<Column> held;  // the value arrays, alive while their spans are read
  if (columns.contains("vars")) {
    if (!py::isinstance<py::dict>(columns["vars"]))
      raise_error("TraceError", "the columns: \"vars\" must be a dict of a name to each variable's values");
    for (const auto& [name, values] : columns["vars"].cast<py::dict>()) {
      const std::string variable = key_name(name);
      held.push_back(integer_column(values, "variable '" + variable + "'"));
      c.variables.push_back(variable);
    }
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

}  // namespace dw::python
