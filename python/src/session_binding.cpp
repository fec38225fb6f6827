// dwatch.Session: the debugging session (sim/session.h) from Python. Commands go through the
// session language's shell (shell/shell.h), as `dwatch session` and the window send them,
// so that their checks, answers and error words are the command line's; the arrays (matches,
// values, series, pictures) are read from the session directly.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>

#include <sstream>
#include <stop_token>

#include "python/src/bindings.h"
#include "python/src/matches.h"
#include "render/image.h"
#include "scenarios/limits.h"
#include "shell/fresh_world.h"
#include "shell/options.h"
#include "shell/shell.h"
#include "shell/utf8_text.h"
#include "shell/view_image.h"
#include "sim/unknown_variables.h"

namespace dw::python {
namespace {

std::string quoted(const std::string& s) { return "'" + s + "'"; }

// A Session is used by one thread at a time: each call marks it busy (under the GIL, which every
// call holds when it starts and ends), and a call from another thread while the first runs
// without the GIL raises RuntimeError instead of racing on the session.
[[noreturn]] void in_use_elsewhere() {
  throw std::runtime_error(
      "this dwatch.Session is in use by another call (another thread): use a Session from one thread at a time, "
      "or one Session per thread");
}

class InUse {
 public:
  explicit InUse(bool& busy) : busy_(busy) {
    if (busy_) in_use_elsewhere();
    busy_ = true;
  }
  InUse(const InUse&) = delete;
  InUse& operator=(const InUse&) = delete;
  ~InUse() { busy_ = false; }

 private:
  bool& busy_;
};

// `values` with numpy's mask where a module is absent (present[i] == 0): a numpy.ma.MaskedArray.
template <class Present>
py::object masked(py::array_t<int64_t> values, const Present& present) {
  py::array_t<bool> absent(static_cast<py::ssize_t>(present.size()));
  for (size_t i = 0; i < present.size(); ++i) absent.mutable_data()[i] = !present[i];
  return py::module_::import("numpy.ma").attr("masked_array")(values, absent);
}

// A session as it was (Session.snapshot): a copy of it kept aside, never stepped, which restore()
// copies back into that session or one of its forks (the same model as loaded). It keeps alive
// the scenario and the world it was copied over.
struct Snapshot {
  std::shared_ptr<const scenarios::Scenario> scenario;
  std::shared_ptr<sim::World> world;
  std::shared_ptr<const sim::Session> session;
};

class Session {
 public:
  Session(const std::filesystem::path& file, std::optional<int64_t> threads, std::optional<int64_t> seed,
          std::optional<int64_t> history_mb, const std::optional<py::dict>& programs) {
    const auto check = [](std::optional<int64_t> v, const scenarios::IntegerRange& range) {
      if (v && (*v < range.min || *v > range.max))
        raise_error("ArgumentError", std::string(range.key) + " must be an integer from " + std::to_string(range.min) +
                                         " to " + std::to_string(range.max));
    };
    check(threads, scenarios::kThreadsRange);
    check(seed, scenarios::kSeedRange);
    check(history_mb, scenarios::kHistoryRange);
    const std::string path = file.string();
    raise_if_missing(path);
    const shell::SessionSource source{.scenario = path, .seed = seed, .threads = threads, .history_mb = history_mb};
    scenarios::ScenarioOverrides overrides;
    if (seed) overrides.seed = static_cast<uint64_t>(*seed);
    overrides.memory_limit = shell::memory_limit_unless(false);
    overrides.python_programs = python_programs(programs);
    std::variant<scenarios::Scenario, std::string> loaded;
    {
      py::gil_scoped_release released;
      loaded = scenarios::load_scenario(path, overrides);
    }
    if (auto* errors = std::get_if<std::string>(&loaded)) {
      std::string message = *errors;
      while (!message.empty() && message.back() == '\n') message.pop_back();
      raise_scenario_error(message);
    }
    scenario_ = std::make_shared<scenarios::Scenario>(std::get<scenarios::Scenario>(std::move(loaded)));
    world_ = std::shared_ptr<sim::World>(scenario_, scenario_->world.get());
    session_ = std::make_unique<sim::Session>(*scenario_->model, *world_, shell::session_options(*scenario_, source));
    shell_ = std::make_unique<shell::Shell>(*scenario_, *session_);
  }

  // An independent copy over a world of its own (sim::Session's copy): the same model, shared.
  Session fork() {
    const InUse in_use = use();
    std::shared_ptr<sim::World> world = shell::fresh_world(*scenario_);
    std::unique_ptr<sim::Session> copy;
    {
      py::gil_scoped_release released;
      copy = std::make_unique<sim::Session>(*session_, *world, session_->threads());
    }
    return Session(scenario_, std::move(world), std::move(copy));
  }

  Snapshot snapshot() {
    const InUse in_use = use();
    py::gil_scoped_release released;  // one thread: a copy kept aside never steps
    return Snapshot{scenario_, world_, std::make_shared<const sim::Session>(*session_, *world_, 1u)};
  }

  void restore(const Snapshot& snapshot) {
    const InUse in_use = use();
    if (snapshot.scenario != scenario_)
      raise_error("ArgumentError",
                  "a snapshot is restored into the session it was taken of, or a fork of it (the same scenario as "
                  "loaded)");
    std::unique_ptr<sim::Session> copy;
    {
      py::gil_scoped_release released;
      copy = std::make_unique<sim::Session>(*snapshot.session, *world_, session_->threads());
    }
    shell_ = std::make_unique<shell::Shell>(*scenario_, *copy);
    session_ = std::move(copy);
  }

  // One line of the session language: its answer as a dict (None for a blank or comment line).
  py::object command(const std::string& line) {
    const InUse in_use = use();
    if (line.find('\n') != std::string::npos) raise_error("CommandError", "one command, on one line");
    const watch::SourceText source("<command>", line);
    auto parsed = shell_->parse(source, 0, 1);
    if (auto* mistakes = std::get_if<std::vector<watch::Diagnostic>>(&parsed)) {
      std::string message = watch::format_diagnostics(source, *mistakes);
      while (!message.empty() && message.back() == '\n') message.pop_back();
      const watch::Location at = source.locate(mistakes->front().span.begin);
      raise_error_at("CommandError", message, source.name(), at.line, at.column);
    }
    const auto& command = std::get<std::optional<shell::Command>>(parsed);
    if (!command) return py::none();
    return execute(*command);
  }

  py::object watch(const std::string& name, const std::string& text, const std::string& algorithm,
                   const std::optional<std::string>& shape, const std::optional<std::string>& states,
                   const std::string& action, uint64_t max_live) {
    const InUse in_use = use();
    // Its name is said in the session language as a word, quoted when it holds a space or '#'
    // (unwatch, action, run's to_match): a quoted word cannot hold '"'.
    if (shell::command_word(name) != name && name.find('"') != std::string::npos)
      raise_error("CommandError", "a watchpoint's name with a space or '#' cannot also hold '\"', not " + quoted(name));
    if (const std::string why = watch::name_problem(name); !why.empty()) raise_error("CommandError", why);
    sim::WatchSpec spec = reading(algorithm, shape, states, max_live);
    if (!sim::read_word(spec, action, sim::WatchWord::Action))
      raise_error("ArgumentError", "action must be 'log', 'pause' or 'count', not " + quoted(action));
    spec.name = name;
    spec.text = text;
    sim::HostedWatchpoint hosted = compile_or_raise(spec);
    if (auto unknown = sim::unknown_variable_mistakes(session_->model(), hosted.watchpoint); !unknown.empty())
      raise_watch_error({hosted.watchpoint.source, std::move(unknown)});
    shell::Command command{.kind = shell::Command::Kind::Watch, .name = name};
    command.watch = std::move(hosted);
    return execute(command);
  }

  Matches matches(const std::string& name) {
    const InUse in_use = use();
    const int w = session_->watch_index(name);
    if (w < 0) raise_error("CommandError", "no watchpoint is named " + quoted(name));
    const sim::MatchList& list = session_->matches(static_cast<uint32_t>(w));
    const auto& slot_names = session_->watches()[static_cast<uint32_t>(w)].hosted.watchpoint.program.slot_names;
    Matches::Builder built;
    built.t.append(list.t);
    built.detected.append(list.detected);
    built.slots.append(std::span<const sim::ModuleId>(list.slots));
    built.count = session_->match_count(static_cast<uint32_t>(w));  // a `count` watchpoint keeps none
    return Matches::make(name, slot_names, std::move(built));
  }

  // One variable of every module at the current step, absent modules masked.
  py::object values(const std::string& variable) {
    const InUse in_use = use();
    const int column = this->column(variable);
    const sim::Model& model = session_->model();
    std::vector<int64_t> all;
    std::vector<uint8_t> present;
    {
      py::gil_scoped_release released;
      const sim::State& state = session_->state();
      all = session_->whole_values(state);
      present = state.present;
    }
    py::array_t<int64_t> out(model.module_count());
    for (uint32_t m = 0; m < model.module_count(); ++m)
      out.mutable_at(m) = all[size_t{m} * model.variable_count() + static_cast<size_t>(column)];
    return masked(out, present);
  }

  // Which modules are present at the current step.
  py::array_t<bool> present() {
    const InUse in_use = use();
    std::vector<uint8_t> present;
    {
      py::gil_scoped_release released;
      present = session_->state().present;
    }
    py::array_t<bool> out(static_cast<py::ssize_t>(present.size()));
    for (size_t m = 0; m < present.size(); ++m) out.mutable_data()[m] = present[m] != 0;
    return out;
  }

  // N(m, t) of every module at the current step, as the watchpoints saw it: compressed rows, the
  // neighbours of m being indices[indptr[m]:indptr[m + 1]] (scipy.sparse.csr_matrix's layout).
  py::tuple neighbours() {
    const InUse in_use = use();
    std::vector<int64_t> indptr, indices;
    {
      py::gil_scoped_release released;
      const sim::NeighborGraph& graph = session_->seen_graph();
      indptr.assign(graph.begin.begin(), graph.begin.end());
      indices.assign(graph.ids.begin(), graph.ids.end());
    }
    const auto read_only = [](const std::vector<int64_t>& v) {
      py::array_t<int64_t> out(static_cast<py::ssize_t>(v.size()), v.data());
      out.attr("flags").attr("writeable") = false;
      return out;
    };
    return py::make_tuple(read_only(indptr), read_only(indices));
  }

  py::object series(int64_t module, const std::string& variable, int64_t first, int64_t last) {
    const InUse in_use = use();
    const int column = this->column(variable);
    if (module < 0 || module >= session_->model().module_count())
      raise_error("CommandError",
                  "M must be an integer from 0 to " + std::to_string(session_->model().module_count() - 1));
    if (first < 0 || last < first || last > session_->latest())
      raise_error("CommandError",
                  "the steps must satisfy 0 <= first <= last <= latest (" + std::to_string(session_->latest()) + ")");
    std::optional<std::vector<int64_t>> values;
    std::vector<uint8_t> present;
    run_cancellable([&](const sim::Control& control) {
      values = session_->series(static_cast<sim::ModuleId>(module), column, first, last, control, &present);
    });
    return masked(py::array_t<int64_t>(static_cast<py::ssize_t>(values->size()), values->data()), present);
  }

  py::array_t<uint8_t> render(int width, int height, const std::optional<py::tuple>& camera) {
    const InUse in_use = use();
    // As the session's `render W H` takes them.
    if (width < 16 || height < 16 || width > 8192 || height > 8192)
      raise_error("ArgumentError", "width and height must be from 16 to 8192 pixels");
    render::Scene scene = shell_->scene();
    if (camera) {
      std::array<double, 3> eye{}, target{};
      try {
        if (camera->size() != 2) throw py::cast_error();
        eye = (*camera)[0].cast<std::array<double, 3>>();
        target = (*camera)[1].cast<std::array<double, 3>>();
      } catch (const py::cast_error&) {
        raise_error("ArgumentError", "camera is (eye, target): two points (x, y, z)");
      }
      // As the command line's and a scenario's camera: refused where it can draw nothing.
      if (const std::string problem = scenarios::camera_problem(eye, target); !problem.empty())
        raise_error("ArgumentError", problem);
      scene.camera_eye = sim::Vec3{float(eye[0]), float(eye[1]), float(eye[2])};
      scene.camera_target = sim::Vec3{float(target[0]), float(target[1]), float(target[2])};
    }
    std::variant<render::Image, std::string> drawn;
    {
      py::gil_scoped_release released;
      drawn = shell::render_view(scene, width, height);
    }
    if (auto* error = std::get_if<std::string>(&drawn)) raise_error("Error", *error);
    const render::Image& image = std::get<render::Image>(drawn);
    py::array_t<uint8_t> out({height, width, 3});
    uint8_t* to = out.mutable_data();
    for (size_t p = 0, n = size_t(width) * size_t(height); p < n; ++p)
      for (size_t c = 0; c < 3; ++c) to[p * 3 + c] = image.rgba[p * 4 + c];
    return out;
  }

  // The current view as a PNG file's bytes, fitted camera: what Jupyter shows for a Session.
  py::bytes png(int width, int height) {
    const InUse in_use = use();
    const render::Scene scene = shell_->scene();
    std::optional<std::vector<uint8_t>> bytes;
    std::string error;
    {
      py::gil_scoped_release released;
      std::variant<render::Image, std::string> drawn = shell::render_view(scene, width, height);
      if (auto* image = std::get_if<render::Image>(&drawn)) bytes = render::encode_png(*image, &error);
      else error = std::get<std::string>(drawn);
    }
    if (!bytes) raise_error("Error", error);
    return py::bytes(reinterpret_cast<const char*>(bytes->data()), bytes->size());
  }

  const sim::Session& session() const {
    if (busy_) in_use_elsewhere();  // another thread's call is changing it
    if (!session_) closed();
    return *session_;
  }

  // Frees the session (its history, the scenario's world) now rather than when Python collects
  // it; any later call raises dwatch.Error. Closing twice does nothing.
  void close() {
    const InUse in_use(busy_);
    shell_.reset();  // it refers to the session and the scenario
    session_.reset();
    world_.reset();
    scenario_.reset();
  }

 private:
  Session(std::shared_ptr<scenarios::Scenario> scenario, std::shared_ptr<sim::World> world,
          std::unique_ptr<sim::Session> session)
      : scenario_(std::move(scenario)), world_(std::move(world)), session_(std::move(session)) {
    shell_ = std::make_unique<shell::Shell>(*scenario_, *session_);
  }

  [[noreturn]] static void closed() { raise_error("Error", "this Session is closed"); }

  // Marks the session in use for one call: another thread's call meanwhile is refused, as is any
  // call once it is closed.
  InUse use() {
    if (!session_) closed();
    return InUse(busy_);
  }

  int column(const std::string& variable) const {
    const int c = session_->model().column(variable);
    if (c < 0) raise_error("CommandError", quoted(variable) + " is no program's variable");
    return c;
  }

  // Runs `work` without the GIL; Ctrl-C (any Python signal handler that raises) stops it between
  // steps, and the exception is raised once the session is consistent again.
  template <class Work>
  void run_cancellable(Work&& work) {
    std::stop_source stop;
    bool interrupted = false;
    const sim::Control control{stop.get_token(), [&](int64_t, int64_t) {
                                 py::gil_scoped_acquire gil;
                                 if (!interrupted && PyErr_CheckSignals() != 0) {
                                   interrupted = true;
                                   stop.request_stop();
                                 }
                               }};
    {
      py::gil_scoped_release released;
      work(control);
    }
    if (interrupted) throw py::error_already_set();  // the signal handler's exception, still set
  }

  py::object execute(const shell::Command& command) {
    std::variant<nlohmann::ordered_json, std::string> answer;
    run_cancellable([&](const sim::Control& control) {
      try {
        answer = shell_->execute(command, control);
      } catch (const std::exception& e) {
        answer = std::string(e.what());
      }
    });
    if (auto* error = std::get_if<std::string>(&answer)) {
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();  // Ctrl-C in a Python program's step
      raise_error("CommandError", *error);
    }
    return py::module_::import("json").attr("loads")(shell::answer_line(std::get<nlohmann::ordered_json>(answer)));
  }

  // Shared with its forks and snapshots (the model is never changed); the world is the scenario's,
  // or a fork's own.
  std::shared_ptr<scenarios::Scenario> scenario_;
  std::shared_ptr<sim::World> world_;
  std::unique_ptr<sim::Session> session_;
  std::unique_ptr<shell::Shell> shell_;
  bool busy_ = false;  // a call is running (InUse)
};

std::string number(int64_t v) { return std::to_string(v); }

// What a Session is: its steps, size, variables and watchpoints.
void add_properties(py::class_<Session>& session) {
  session
      .def_property_readonly(
          "current", [](const Session& s) { return s.session().current(); }, "The step shown (-1 before the first).")
      .def_property_readonly(
          "latest", [](const Session& s) { return s.session().latest(); }, "The last step simulated on this branch.")
      .def_property_readonly(
          "end", [](const Session& s) { return s.session().end(); }, "The scenario's steps.")
      .def_property_readonly(
          "modules", [](const Session& s) { return s.session().model().module_count(); },
          "How many modules the ensemble has (ids 0 .. modules - 1).")
      .def_property_readonly(
          "variables", [](const Session& s) { return s.session().model().universe.variables; },
          "The programs' variables.")
      .def_property_readonly(
          "watches",
          [](const Session& s) {
            std::vector<std::string> names;
            for (const sim::HostedWatchpoint& h : s.session().watches().hosted()) names.push_back(h.watchpoint.name);
            return names;
          },
          "The watchpoints' names.");
}

// The class's docstring (help(dwatch.Session)).
constexpr const char* kSessionDoc = R"(A debugging session over a scenario file, as `dwatch session` runs it.

The whole history stays: seek anywhere, intervene to start a branch, add watchpoints that are
evaluated over the past. Commands answer dicts, the JSON objects `dwatch session` prints; a wrong
or failed command raises CommandError with the command line's words. Stepping runs without the
GIL; Ctrl-C stops a long command between steps (the session stays consistent) and raises
KeyboardInterrupt. Use a Session from one thread at a time (another thread may use another): a
call while another thread's runs raises RuntimeError. values() and series() are numpy masked
arrays, absent (removed) modules masked; present() says which modules are there.)";

// Session.why and Session.why_match: the session's `why` (docs/why.md), its answer as a dict.
void add_why(py::class_<Session>& session) {
  session
      .def(
          "why",
          [](Session& s, int64_t m, const std::string& var, std::optional<int64_t> t, int64_t depth, bool narrow) {
            return s.command("why " + number(m) + " " + var + (t ? " " + number(*t) : "") + " --depth " +
                             number(depth) + (narrow ? " --narrow" : ""));
          },
          py::arg("m"), py::arg("var"), py::arg("t") = py::none(), py::kw_only(), py::arg("depth") = 3,
          py::arg("narrow") = false,
          "Why variable var of module m is what it is at step t (default: the current step): its causal history "
          "(`why`, docs/session.md) as a dict: the value's origin, the cone's events (who wrote what, old and new, "
          "their causes), the messages between them and the neighbour changes, depth steps deep; narrow keeps "
          "only the changes and the new messages. The cursor stays.")
      .def(
          "why_match",
          [](Session& s, const std::string& w, int64_t row, int64_t depth, bool narrow) {
            return s.command("why match " + shell::command_word(w) + " " + number(row) + " --depth " + number(depth) +
                             (narrow ? " --narrow" : ""));
          },
          py::arg("w"), py::arg("row"), py::kw_only(), py::arg("depth") = 3, py::arg("narrow") = false,
          "Why watchpoint w matched in its row-th match (a row of matches(w), from 0): the union of the cones of "
          "the values it read, its group's events marked, as why() answers.");
}

// Session.fork, snapshot and restore (sim::Session's copy), and what a Snapshot shows.
void add_copies(py::module_& m, py::class_<Session>& session) {
  py::class_<Snapshot>(m, "Snapshot", "A Session as it was (Session.snapshot()), to restore() it.")
      .def_property_readonly(
          "current", [](const Snapshot& s) { return s.session->current(); }, "The step that was current.")
      .def_property_readonly(
          "latest", [](const Snapshot& s) { return s.session->latest(); }, "The last step that was simulated.")
      .def("__repr__", [](const Snapshot& s) {
        return "<dwatch.Snapshot at step " + number(s.session->current()) + " of " + number(s.session->latest()) + ">";
      });
  session
      .def("fork", &Session::fork,
           "An independent copy of the session, to try another branch beside this one: the same step, history, "
           "branch, watchpoints and matches; what either does next leaves the other as it was.")
      .def("snapshot", &Session::snapshot,
           "The session as it is now, everything that changes (the step, the history and branch, the watchpoints "
           "and what they found), for restore(): MuJoCo's mj_getState. It holds a copy of the history.")
      .def("restore", &Session::restore, py::arg("snapshot"),
           "Makes the session what it was at snapshot() (MuJoCo's mj_setState): running on then gives the states, "
           "hashes and matches of the run that never went back. A snapshot restores into the session it was taken "
           "of or a fork of it, as often as wanted.");
}

}  // namespace

void add_session(py::module_& m) {
  py::class_<Session> session(m, "Session", kSessionDoc);
  session.def("close", &Session::close, "Frees the session now; any later call raises Error.")
      .def("__enter__", [](py::object self) { return self; })
      .def(
          "__exit__", [](Session& s, const py::args&) { s.close(); },
          "Closes the session at the end of a `with` block.");
  session
      .def(py::init<const std::filesystem::path&, std::optional<int64_t>, std::optional<int64_t>,
                    std::optional<int64_t>, const std::optional<py::dict>&>(),
           py::arg("scenario"), py::arg("threads") = py::none(), py::arg("seed") = py::none(),
           py::arg("history_mb") = py::none(), py::arg("programs") = py::none(),
           "Loads a scenario file (TOML); threads, seed and history_mb override the scenario's; programs gives the "
           "Python programs its [[program]] python = NAME tables name. Raises ScenarioError.")
      .def("command", &Session::command, py::arg("line"),
           "Any command of the session language (`help` lists them); its answer as a dict.")
      .def(
          "step", [](Session& s, int64_t n) { return s.command("step " + number(n)); }, py::arg("n") = 1,
          "Runs n steps (stops at a pause match).")
      .def(
          "run",
          [](Session& s, std::optional<int64_t> t, std::optional<std::string> to_match) {
            return s.command("run" + (t ? " " + number(*t) : "") +
                             (to_match ? " --to-match " + shell::command_word(*to_match) : ""));
          },
          py::arg("t") = py::none(), py::arg("to_match") = py::none(),
          "Runs until step t is current (default: the scenario's last step), a pause match, or the next match of "
          "watchpoint to_match.")
      .def(
          "continue_", [](Session& s) { return s.command("continue"); },
          "Runs on past the pause that stopped the cursor (`continue`).")
      .def(
          "seek", [](Session& s, int64_t t) { return s.command("seek " + number(t)); }, py::arg("t"),
          "Makes step t current; nothing is lost.")
      .def(
          "set",
          [](Session& s, int64_t module, const std::string& variable, int64_t value) {
            return s.command("set " + number(module) + " " + variable + " " + number(value));
          },
          py::arg("module"), py::arg("variable"), py::arg("value"),
          "Intervention at the current step: a new branch where the module's variable has this value.")
      .def(
          "remove", [](Session& s, int64_t module) { return s.command("remove " + number(module)); }, py::arg("module"),
          "Intervention: the module leaves the ensemble.")
      .def(
          "push",
          [](Session& s, int64_t module, double x, double y, double z) {
            const auto real = [](double v) {
              std::ostringstream out;
              out.precision(17);
              out << v;
              return out.str();
            };
            return s.command("push " + number(module) + " " + real(x) + " " + real(y) + " " + real(z));
          },
          py::arg("module"), py::arg("x"), py::arg("y"), py::arg("z"),
          "Intervention (physics): an impulse of (x, y, z) N s on the module's body.")
      .def("watch", &Session::watch, py::arg("name"), py::arg("text"), py::arg("algorithm") = "distributed",
           py::arg("shape") = py::none(), py::arg("states") = py::none(), py::arg("action") = "log",
           py::arg("max_live") = sim::kDefaultMatchBudget,
           "Adds or replaces a watchpoint, evaluated over the whole history. Raises WatchError.")
      .def(
          "unwatch",
          [](Session& s, const std::string& name) { return s.command("unwatch " + shell::command_word(name)); },
          py::arg("name"), "Removes a watchpoint.")
      .def(
          "action",
          [](Session& s, const std::string& name, const std::string& what) {
            return s.command("action " + shell::command_word(name) + " " + what);
          },
          py::arg("name"), py::arg("action"),
          "What the watchpoint does with its matches from now on: log, pause, count.")
      .def("matches", &Session::matches, py::arg("name"), "The watchpoint's matches over the history, as arrays.")

      .def(
          "state", [](Session& s, int64_t module) { return s.command("state " + number(module)); }, py::arg("module"),
          "The module at the current step: variables, neighbours, and with physics its pose after the step "
          "('pose') and the one its neighbours were measured from, at the end of the step before "
          "('nbrs_measured_from').")
      .def("values", &Session::values, py::arg("variable"),
           "One variable of every module at the current step: an int64 numpy.ma.MaskedArray, shape (modules,), "
           "absent modules masked.")
      .def("neighbours", &Session::neighbours,
           "N(m, t) of every module at the current step, as the watchpoints saw it, as compressed rows: (indptr, "
           "indices), int64, read-only; module m's neighbours are indices[indptr[m]:indptr[m + 1]], sorted "
           "(scipy.sparse.csr_matrix((np.ones(len(indices)), indices, indptr)) is the adjacency matrix).")
      .def(
          "_repr_png_", [](Session& s) { return s.png(640, 360); },
          "The current view (640 x 360, fitted camera) as PNG bytes: what a Jupyter notebook shows for a Session.")
      .def("present", &Session::present, "Which modules are present at the current step: bool, shape (modules,).")
      .def("series", &Session::series, py::arg("module"), py::arg("variable"), py::arg("first"), py::arg("last"),
           "One variable of one module over steps first..last: an int64 numpy.ma.MaskedArray, shape (last - first "
           "+ 1,), masked at the steps the module was absent.")
      .def(
          "hash", [](Session& s) { return s.command("hash").attr("__getitem__")("hash"); },
          "The state hash at the current step, as `dwatch session`'s `hash` answers it.")
      .def("render", &Session::render, py::arg("width") = 1280, py::arg("height") = 720, py::arg("camera") = py::none(),
           "The 3D view of the current step, its matches highlighted, as `render` draws it: uint8, shape (height, "
           "width, 3). camera: (eye, target), two points; default: fitted.")
      .def(
          "save",
          [](Session& s, const std::filesystem::path& path, bool overwrite) {
            return s.command("save " + shell::command_word(path.string()) + (overwrite ? " overwrite" : ""));
          },
          py::arg("path"), py::arg("overwrite") = false, "This session as a scenario file.")
      .def(
          "record",
          [](Session& s, const std::filesystem::path& path, bool messages) {
            return s.command("record " + shell::command_word(path.string()) + (messages ? " --messages" : ""));
          },
          py::arg("path"), py::arg("messages") = false,
          "The trace of steps 0..latest (wptrace v1); messages: each line also says what its module read, so that "
          "`dwatch why TRACE ...` answers as `why` does.");
  add_copies(m, session);
  add_properties(session);
  add_why(session);
}

}  // namespace dw::python
