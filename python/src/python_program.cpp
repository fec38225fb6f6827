// Host programs written in Python (docs/python.md#robot-logic-in-python): the classes given to
// `dwatch.Session(scenario, programs={"mine": Mine})`, which a scenario's [[program]] names with
// `python = "mine"`, each made a sim::HostProgram, and `m`, the module's side of the host-program
// API (sim/host_program.h) that their step(m) is called with (dwatch.Module), the same as the Lua
// hosts' (scenarios/lua_host/lua_module_api.cpp).
//
// A class is made once per session (an instance given is used as it is), and its step(m) is
// called once per present module and step. The calls come one at a time, in module id order, on
// the thread that steps the session (HostProgram::in_module_order), each holding the GIL: the
// same calls in the same order on every thread count. An exception in step(m) stops the run as a
// program error naming the program, the module and the step.
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <utility>
#include <variant>
#include <vector>

#include "python/src/bindings.h"
#include "scenarios/table_reader.h"

namespace dw::python {
namespace {

// A Python object owned from C++ where the GIL may not be held: let go of with the GIL taken
// (never after the interpreter has ended: then it is left as it is).
struct Held {
  py::object object;
  explicit Held(py::object o) : object(std::move(o)) {}
  Held(const Held&) = delete;
  Held& operator=(const Held&) = delete;
  ~Held() {
    if (!Py_IsInitialized()) {
      object.release();
      return;
    }
    py::gil_scoped_acquire gil;
    object = py::object();
  }
};

// What a class declares: `vars`, the variables' names in order, and `params`, name -> default.
struct Declared {
  std::vector<std::string> vars;
  std::vector<std::pair<std::string, int64_t>> params;
  std::unordered_map<std::string, uint32_t> var_index, param_index;
};

// `m` during one call of step(m); unusable once the call has returned.
class ModuleView {
 public:
  ModuleView(sim::ModuleContext& m, const Declared& declared) : m_(&m), declared_(&declared) {}

  sim::ModuleContext& module() const {
    if (!m_) throw std::runtime_error("this Module is step(m)'s for one call, and that call has returned");
    return *m_;
  }
  void end() { m_ = nullptr; }

  int64_t get(const std::string& name) const { return module().get(variable(name)); }
  void set(const std::string& name, int64_t value) { module().set(variable(name), value); }
  int64_t param(const std::string& name) const {
    const auto it = declared_->param_index.find(name);
    if (it == declared_->param_index.end())
      throw py::key_error("'" + name + "' is not a parameter of this program (declare it in the class's params)");
    return declared_->params[it->second].second;
  }
  py::list neighbors() const {
    py::list out;
    for (sim::ModuleId n : module().neighbors()) out.append(n);
    return out;
  }
  // [(sender, [words]), ...]: by sender id, then in sending order.
  py::list inbox() const {
    py::list out;
    for (const sim::Message& message : module().inbox()) {
      py::list words;
      for (int64_t w : message.payload()) words.append(w);
      out.append(py::make_tuple(message.from, std::move(words)));
    }
    return out;
  }
  void send(int64_t to, const std::vector<int64_t>& words) {
    sim::ModuleContext& m = module();
    if (to < 0 || to > int64_t(UINT32_MAX) || !m.is_neighbor(sim::ModuleId(to)))
      throw py::value_error("module " + std::to_string(m.id()) + " sent to " + std::to_string(to) +
                            ", which is not its neighbour");
    m.send(sim::ModuleId(to), checked(words));
  }
  void broadcast(const std::vector<int64_t>& words) { module().broadcast(checked(words)); }
  // random(n): 0 .. n - 1; random(0): 64 random bits, 0 .. 2**64 - 1. Each draw of a call reads
  // its own stream, the first stream 0 (as the Lua hosts' m:random).
  py::int_ random(int64_t n) {
    if (n < 0) throw py::value_error("random(n) needs n >= 1 (or 0 for 64 bits), not " + std::to_string(n));
    sim::ModuleContext& m = module();
    const uint32_t stream = draws_++;
    if (n == 0) return py::int_(m.random(stream));
    return py::int_(m.uniform(n, stream));
  }
  py::tuple position() const {
    const sim::Vec3& p = body("position").pose().position;
    return py::make_tuple(p[0], p[1], p[2]);
  }
  bool moving() const { return body("moving").moving(); }
  void move(double x, double y, double z) { body("move").move(vector("move", x, y, z)); }
  void push(double x, double y, double z) { body("push").push(vector("push", x, y, z)); }
  void pivot(int64_t about, double x, double y, double z) {
    sim::ModuleContext& m = body("pivot");
    if (about < 0 || about > int64_t(UINT32_MAX) || !m.is_neighbor(sim::ModuleId(about)))
      throw py::value_error("module " + std::to_string(m.id()) + " pivots about " + std::to_string(about) +
                            ", which is not its neighbour");
    m.pivot(sim::ModuleId(about), vector("pivot", x, y, z));
  }

 private:
  uint32_t variable(const std::string& name) const {
    const auto it = declared_->var_index.find(name);
    if (it == declared_->var_index.end())
      throw py::key_error("'" + name + "' is not a variable of this program (declare it in the class's vars)");
    return it->second;
  }
  static std::span<const int64_t> checked(const std::vector<int64_t>& words) {
    if (words.size() > sim::Message::kMaxWords)
      throw py::value_error("a message holds at most " + std::to_string(sim::Message::kMaxWords) + " integers, not " +
                            std::to_string(words.size()));
    return words;
  }
  sim::ModuleContext& body(const char* method) const {
    sim::ModuleContext& m = module();
    if (!m.has_body())
      throw std::runtime_error(std::string(method) +
                               "() needs a body, and this world has none (the scenario's [physics] is off)");
    return m;
  }
  // A NaN or an infinity would silently corrupt the world's poses: refused, naming the call.
  static sim::Vec3 vector(const char* method, double x, double y, double z) {
    const double given[3] = {x, y, z};
    sim::Vec3 v;
    for (size_t i = 0; i < 3; ++i) {
      if (!std::isfinite(given[i]) || std::abs(given[i]) > std::numeric_limits<float>::max())
        throw py::value_error(std::string(method) + ": its " + "xyz"[i] + " is " + std::to_string(given[i]) +
                              ", not a finite number");
      v[i] = float(given[i]);
    }
    return v;
  }

  sim::ModuleContext* m_;
  const Declared* declared_;
  uint32_t draws_ = 0;
};

// "ZeroDivisionError: division by zero (at file.py:12, in step)": the exception and the line
// of the user's code it was raised at.
std::string described(py::error_already_set& e) {
  std::string out = py::str(e.type().attr("__name__"));
  const std::string text = py::str(e.value());
  if (!text.empty()) out += ": " + text;
  if (e.trace()) {
    const py::list frames = py::module_::import("traceback").attr("extract_tb")(e.trace());
    if (!frames.empty()) {
      const py::object last = frames[frames.size() - 1];
      out += " (at " + py::str(last.attr("filename")).cast<std::string>() + ":" +
             py::str(last.attr("lineno")).cast<std::string>() + ", in " +
             py::str(last.attr("name")).cast<std::string>() + ")";
    }
  }
  return out;
}

class PythonProgram final : public sim::HostProgram {
 public:
  PythonProgram(std::string name, std::shared_ptr<Held> instance, std::shared_ptr<Held> step, Declared declared)
      : name_(std::move(name)),
        instance_(std::move(instance)),
        step_(std::move(step)),
        declared_(std::move(declared)) {}

  std::string_view name() const override { return name_; }
  std::vector<sim::VariableSpec> variables() const override {
    std::vector<sim::VariableSpec> out;
    for (const std::string& v : declared_.vars) out.push_back({v, 0});
    return out;
  }
  bool in_module_order() const override { return true; }
  void step(sim::ModuleContext& m) const override {
    py::gil_scoped_acquire gil;
    try {
      py::object view = py::cast(ModuleView(m, declared_), py::return_value_policy::move);
      try {
        step_->object(view);
      } catch (...) {
        view.cast<ModuleView&>().end();
        throw;
      }
      view.cast<ModuleView&>().end();
    } catch (py::error_already_set& e) {
      std::string what;
      try {
        what = described(e);
      } catch (py::error_already_set&) {
        what = "an exception that could not be described";
      }
      m.fail("at step " + std::to_string(m.step()) + ": " + what);
      // Ctrl-C while the user's code ran: the step fails (the session stays at the last whole
      // one), and the interrupt is raised again for the command to raise as KeyboardInterrupt
      // (after `described`, whose Python code would take it).
      if (e.matches(PyExc_KeyboardInterrupt)) PyErr_SetInterrupt();
    }
  }

 private:
  std::string name_;
  std::shared_ptr<Held> instance_, step_;
  Declared declared_;
};

// What `instance` declares (its vars and params), or the reason it declares it wrongly.
std::variant<Declared, std::string> declared_by(const py::object& instance, const std::string& shown) {
  Declared d;
  if (!py::hasattr(instance, "vars") || !py::isinstance<py::sequence>(instance.attr("vars")) ||
      py::isinstance<py::str>(instance.attr("vars")))
    return shown + " must declare vars, a list of its variables' names (str)";
  for (const py::handle v : instance.attr("vars")) {
    if (!py::isinstance<py::str>(v)) return shown + ".vars must hold names (str), not " + std::string(py::repr(v));
    std::string name = v.cast<std::string>();
    if (name.empty() || d.var_index.count(name)) return shown + ".vars names '" + name + "' twice, or an empty name";
    d.var_index[name] = uint32_t(d.vars.size());
    d.vars.push_back(std::move(name));
  }
  if (py::hasattr(instance, "params")) {
    const py::object params = instance.attr("params");
    if (!py::isinstance<py::dict>(params)) return shown + ".params must be a dict of name -> default (int)";
    for (const auto [key, value] : params.cast<py::dict>()) {
      if (!py::isinstance<py::str>(key) || !py::isinstance<py::int_>(value) || py::isinstance<py::bool_>(value))
        return shown + ".params must map names (str) to integer defaults, not " + std::string(py::repr(key)) + ": " +
               std::string(py::repr(value));
      std::string name = key.cast<std::string>();
      const int64_t initial = value.cast<int64_t>();
      d.param_index[name] = uint32_t(d.params.size());
      d.params.emplace_back(std::move(name), initial);
    }
  }
  if (!py::hasattr(instance, "step") || !PyCallable_Check(instance.attr("step").ptr()))
    return shown + " must define step(self, m)";
  return d;
}

// The program `name` from `given` (a class, made here, or an instance), with its [[program]]
// table's parameters; nullptr with the mistake reported at the table.
std::unique_ptr<const sim::HostProgram> make_program(const std::string& name, const Held& given,
                                                     scenarios::TableReader& params) {
  py::gil_scoped_acquire gil;
  const bool is_class = py::isinstance<py::type>(given.object);
  const py::object type = is_class ? given.object : py::object(given.object.attr("__class__"));
  const std::string shown = "the Python program \"" + name + "\" (" + std::string(py::str(type.attr("__name__"))) + ")";
  py::object instance;
  try {
    instance = is_class ? given.object() : given.object;
  } catch (py::error_already_set& e) {
    params.error("python", shown + " could not be made: " + described(e));
    return nullptr;
  }
  std::variant<Declared, std::string> declared;
  try {
    declared = declared_by(instance, shown);
  } catch (py::error_already_set& e) {
    declared = shown + ": " + described(e);
  } catch (const py::cast_error& e) {
    declared = shown + ": " + e.what();
  }
  if (auto* why = std::get_if<std::string>(&declared)) {
    params.error("python", *why);
    return nullptr;
  }
  Declared& d = std::get<Declared>(declared);
  bool ok = true;
  for (auto& [param, value] : d.params)
    if (params.has(param)) {
      const auto v = params.integer(param, INT64_MIN, INT64_MAX);
      if (v) value = *v;
      else ok = false;
    }
  if (!ok) return nullptr;
  auto step = std::make_shared<Held>(instance.attr("step"));
  return std::make_unique<PythonProgram>(name, std::make_shared<Held>(std::move(instance)), std::move(step),
                                         std::move(d));
}

}  // namespace

scenarios::ProvidedPrograms python_programs(const std::optional<py::dict>& programs) {
  scenarios::ProvidedPrograms out;
  if (!programs) return out;
  for (const auto [key, value] : *programs) {
    if (!py::isinstance<py::str>(key))
      raise_error("ArgumentError", "programs maps names (str) to classes, not " + std::string(py::repr(key)));
    const std::string name = key.cast<std::string>();
    auto given = std::make_shared<Held>(py::reinterpret_borrow<py::object>(value));
    out[name] = [name, given](scenarios::TableReader& params) { return make_program(name, *given, params); };
  }
  return out;
}

void add_python_programs(py::module_& m) {
  py::class_<ModuleView>(m, "Module",
                         "A module's side of the host-program API during one call of a Python program's step(m).")
      .def_property_readonly(
          "id", [](const ModuleView& v) { return v.module().id(); }, "This module's id.")
      .def_property_readonly(
          "step", [](const ModuleView& v) { return v.module().step(); }, "The step being run.")
      .def("get", &ModuleView::get, py::arg("name"), "A variable's value at the step before (its initial value at 0).")
      .def("set", &ModuleView::set, py::arg("name"), py::arg("value"), "Assigns the variable's value at this step.")
      .def("param", &ModuleView::param, py::arg("name"), "A parameter's value (the scenario's, or the default).")
      .def("neighbors", &ModuleView::neighbors, "The neighbours' ids, ascending.")
      .def("inbox", &ModuleView::inbox, "This program's messages of the step before: [(sender, [words]), ...].")
      .def("send", &ModuleView::send, py::arg("to"), py::arg("words"), "Sends up to 8 integers to a neighbour.")
      .def("broadcast", &ModuleView::broadcast, py::arg("words"), "Sends the same message to every neighbour.")
      .def("random", &ModuleView::random, py::arg("n"), "0 .. n - 1 (n = 0: 64 bits), a pure function of the run.")
      .def("position", &ModuleView::position, "The body's centre (x, y, z) as the step began; physics only.")
      .def("moving", &ModuleView::moving, "Whether a lattice move is under way; physics only.")
      .def("move", &ModuleView::move, py::arg("x"), py::arg("y"), py::arg("z"), "A lattice move; physics only.")
      .def("push", &ModuleView::push, py::arg("x"), py::arg("y"), py::arg("z"), "An impulse; physics only.")
      .def("pivot", &ModuleView::pivot, py::arg("about"), py::arg("x"), py::arg("y"), py::arg("z"),
           "A pivot about a neighbour into the cell at (x, y, z) from this one; physics only.");
}

}  // namespace dw::python
