#include "scenarios/scenario.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "physics/bullet_world.h"
#include "scenarios/lua_host/lua_program.h"
#include "scenarios/memory_estimate.h"
#include "scenarios/programs/programs.h"
#include "scenarios/table_reader.h"
#include "sim/lattice.h"
#include "sim/read_file.h"
#include "watch/watchpoint.h"

namespace dw::scenarios {

namespace {

// toml++ nests a table per part of a dotted key (`a.b.c = 1`, `[a.b.c]`) by recursion, and its
// depth limit counts only brackets and braces: 40,000 parts crashed it. The offset of the dot that
// makes a key longer than this, or nothing. Floats (1.5) and strings hold dots that are no key's:
// a run of parts ends at any character a key cannot hold.
constexpr size_t kMaxKeyParts = 256;
std::optional<size_t> over_deep_dotted_key(std::string_view text) {
  size_t dots = 0;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '"' || c == '\'') {  // a string, or a quoted part: skipped whole
      const bool triple = text.substr(i, 3) == std::string_view(c == '"' ? "\"\"\"" : "\'\'\'");
      const std::string_view end = triple ? text.substr(i, 3) : text.substr(i, 1);
      size_t j = i + end.size();
      while (j < text.size() && text.substr(j, end.size()) != end) j += (c == '"' && text[j] == '\\') ? 2 : 1;
      i = j + end.size() - 1;
    } else if (c == '#') {
      while (i < text.size() && text[i] != '\n') ++i;
      dots = 0;
    } else if (c == '.') {
      if (++dots >= kMaxKeyParts) return i;
    } else if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == ' ' || c == '\t')) {
      dots = 0;
    }
  }
  return std::nullopt;
}

// Positions (props, the camera) in module sizes: far beyond any lattice, and finite.

// Where the watchpoint text's own characters start in the file: compiled with that base, its
// spans and diagnostics point into the scenario file itself, and it keeps only its own text.
// Nothing when the string was written with escapes, whose value differs from its spelling.
std::optional<uint32_t> text_in_place(const FileDiagnostics& d, const toml::node& value, const std::string& text) {
  const std::string& file = d.source().text();
  const uint32_t begin = d.offset(value.source().begin);
  for (std::string_view quote : {"'''", "\"\"\"", "'", "\""}) {
    if (file.compare(begin, quote.size(), quote) != 0) continue;
    size_t start = begin + quote.size();
    if (quote.size() == 3 && file.compare(start, 1, "\n") == 0) ++start;  // TOML trims it
    else if (quote.size() == 3 && file.compare(start, 2, "\r\n") == 0) start += 2;
    if (file.compare(start, text.size(), text) != 0) return std::nullopt;
    return static_cast<uint32_t>(start);
  }
  return std::nullopt;
}

struct Loader {
  std::string path;
  watch::SourceText source;
  FileDiagnostics diagnostics{source};
  std::string extra;                // diagnostics rendered against other files (watchpoint files)
  std::vector<std::string> inputs;  // the files read besides the scenario (watchpoint files)
  std::vector<ScriptSource> scripts;
  // The files it names that are FIFOs share one wait: a scenario naming the same FIFO a thousand
  // times holds dwatch no longer than one naming it once.
  const std::shared_ptr<LuaMemoryPool> lua_memory = std::make_shared<LuaMemoryPool>();
  const std::chrono::steady_clock::time_point fifo_deadline = std::chrono::steady_clock::now() + sim::kFifoWriterWait;

  Loader(std::string p, std::string text) : path(p), source(std::move(p), std::move(text)) {}

  std::optional<watch::Algorithm> algorithm(TableReader& r) {
    const auto s = r.string("algorithm");
    if (!s) return std::nullopt;
    if (auto a = watch::parse_algorithm(*s)) return a;
    r.error("algorithm", "'algorithm' must be " + watch::algorithm_names() + ", not \"" + *s + "\"");
    return std::nullopt;
  }

  std::optional<watch::GroupShape> shape(TableReader& r) {
    const auto s = r.string("shape");
    if (!s) return std::nullopt;
    if (auto v = watch::parse_shape(*s)) return v;
    r.error("shape", "'shape' must be " + watch::shape_names() + ", not \"" + *s + "\"");
    return std::nullopt;
  }

  std::optional<watch::States> states(TableReader& r) {
    const auto s = r.string("states");
    if (!s) return std::nullopt;
    if (auto v = watch::parse_states(*s)) return v;
    r.error("states", "'states' must be " + watch::states_names() + ", not \"" + *s + "\"");
    return std::nullopt;
  }

  std::optional<sim::MatchAction> action(TableReader& r) {
    const auto s = r.string("action");
    if (!s) return std::nullopt;
    if (auto a = sim::parse_action(*s)) return a;
    r.error("action", "'action' must be " + sim::action_names() + ", not \"" + *s + "\"");
    return std::nullopt;
  }

  // The lattice, once its size is known to fit: within `overrides.max_modules`, and (when a limit
  // is given) its memory estimate within the limit, checked before anything is allocated.
  std::optional<sim::Lattice> lattice(TableReader& root, const ScenarioOverrides& overrides, bool physics,
                                      uint64_t history_mb) {
    const uint64_t max_modules = overrides.max_modules;
    const toml::table* t = root.table("lattice");
    if (!t) {
      if (!root.has("lattice")) root.missing("lattice");
      return std::nullopt;
    }
    TableReader r(*t, diagnostics, "[lattice]");
    sim::LatticeSpec spec;
    bool ok = true;
    const auto kind_name = r.string("kind");
    std::optional<sim::LatticeKind> kind;
    if (kind_name) {
      kind = sim::lattice_from_name(*kind_name);
      if (!kind)
        r.error("kind", "unknown lattice kind \"" + *kind_name + "\" (cubic, square2d, hex2d, ring, line, fcc)");
    } else if (!r.has("kind")) {
      r.missing("kind");
    }
    const auto size = r.integers("size", kSizeRange.min, kSizeRange.max, 1, 3);
    if (!size && !r.has("size")) r.missing("size");
    // Boxes of cells left empty: [[lattice.empty]] from = [x, y, z], to = [x, y, z] (inclusive).
    std::vector<std::array<std::vector<int64_t>, 2>> empty;
    for (const toml::table* box : r.tables("empty")) {
      TableReader e(*box, diagnostics, "[[lattice.empty]]");
      auto from = e.integers("from", 0, 1'000'000, 3, 3), to = e.integers("to", 0, 1'000'000, 3, 3);
      if (!from && !e.has("from")) e.missing("from");
      if (!to && !e.has("to")) e.missing("to");
      if (from && to)
        for (size_t i = 0; i < 3; ++i)
          if ((*from)[i] > (*to)[i]) {
            e.error("to",
                    "each coordinate of 'to' must be at least the one of 'from' (the box is from..to, inclusive), "
                    "not " +
                        std::to_string((*to)[i]) + " < " + std::to_string((*from)[i]));
            from.reset();
            break;
          }
      e.finish();
      if (from && to) empty.push_back({*from, *to});
      else ok = false;
    }
    r.finish();
    if (!kind || !size) return std::nullopt;
    spec.kind = *kind;
    const size_t dims = static_cast<size_t>(sim::lattice_dimensions(*kind));
    if (size->size() != dims) {
      r.error("size", "a " + std::string(sim::lattice_name(*kind)) + " lattice takes " + std::to_string(dims) +
                          " size" + (dims == 1 ? "" : "s") + ", not " + std::to_string(size->size()));
      return std::nullopt;
    }
    for (size_t i = 0; i < dims; ++i) spec.size[i] = static_cast<uint32_t>((*size)[i]);
    if (spec.module_count() > max_modules) {
      r.error("size", "that is " + std::to_string(spec.module_count()) + " modules; the most is " +
                          std::to_string(max_modules));
      ok = false;
    } else if (overrides.memory_limit > 0 &&
               memory_estimate(spec.module_count(), physics, history_mb) > overrides.memory_limit) {
      r.error("size", memory_refusal(spec.module_count(), physics, history_mb, overrides.memory_limit));
      ok = false;
    }
    if (*kind == sim::LatticeKind::Ring && spec.size[0] < 3) {
      r.error("size", "a ring needs at least 3 modules");
      ok = false;
    }
    std::vector<sim::LatticeBox> boxes;
    for (size_t b = 0; b < empty.size(); ++b) {
      const auto& [from, to] = empty[b];
      boxes.push_back({{{uint32_t(from[0]), uint32_t(from[1]), uint32_t(from[2])},
                        {uint32_t(to[0]), uint32_t(to[1]), uint32_t(to[2])}}});
      for (size_t i = 0; i < 3; ++i)
        if (from[i] >= int64_t{spec.size[i]}) {
          r.error("empty", "box " + std::to_string(b + 1) + " (from [" + std::to_string(from[0]) + ", " +
                               std::to_string(from[1]) + ", " + std::to_string(from[2]) +
                               "]) lies outside the lattice, whose cells go up to [" +
                               std::to_string(spec.size[0] - 1) + ", " + std::to_string(spec.size[1] - 1) + ", " +
                               std::to_string(spec.size[2] - 1) + "]: it would empty nothing");
          ok = false;
          break;
        }
    }
    if (!ok) return std::nullopt;
    // A physical world's contacts make its graph (sim::Lattice::graph): none is made here.
    sim::Lattice l = sim::make_lattice(spec, !physics);
    sim::leave_empty(l, boxes);
    if (std::none_of(l.occupied.begin(), l.occupied.end(), [](uint8_t o) { return o != 0; })) {
      r.error("empty", "these boxes leave every cell of the lattice empty: there is no module to run");
      return std::nullopt;
    }
    return l;
  }

  std::optional<physics::ModuleShape> shape(TableReader& r, std::string_view key) {
    const auto name = r.string(key);
    if (!name) return std::nullopt;
    if (*name == "box") return physics::ModuleShape::Box;
    if (*name == "cylinder") return physics::ModuleShape::Cylinder;
    if (*name == "sphere") return physics::ModuleShape::Sphere;
    r.error(key, "'" + std::string(key) + "' must be \"box\", \"cylinder\" or \"sphere\", not \"" + *name + "\"");
    return std::nullopt;
  }

  static sim::Vec3 vec3(const std::optional<std::vector<double>>& v, sim::Vec3 otherwise) {
    return v ? sim::Vec3{float((*v)[0]), float((*v)[1]), float((*v)[2])} : otherwise;
  }

  // [physics]: nothing when it is off (a static lattice).
  std::optional<physics::PhysicsSettings> physics_settings(TableReader& root) {
    const toml::table* t = root.table("physics");
    if (!t) return std::nullopt;
    TableReader r(*t, diagnostics, "[physics]");
    physics::PhysicsSettings p;
    const bool on = r.boolean("enabled").value_or(false);
    p.dt = float(r.number("dt", 1e-4, 1).value_or(p.dt));
    p.gravity = vec3(r.numbers("gravity", 3, -1000, 1000), p.gravity);  // m/s^2: 100 g either way
    p.shape = shape(r, "shape");
    p.module_mass = float(r.number("module_mass", 1e-3, 1e6).value_or(p.module_mass));
    p.contact_threshold = float(
        r.number("contact_threshold", 0, physics::PhysicsSettings::kMaxContactThreshold).value_or(p.contact_threshold));
    p.bonds = r.boolean("bonds").value_or(p.bonds);
    p.anchor = r.boolean("anchor").value_or(p.anchor);
    p.break_force = float(r.number("break_force", 0, 1e12).value_or(p.break_force));
    p.friction = float(r.number("friction", 0, 10).value_or(p.friction));
    p.restitution = float(r.number("restitution", 0, 1).value_or(p.restitution));
    p.solver_iterations = int(r.integer("solver_iterations", 1, 1000).value_or(p.solver_iterations));
    p.move_steps = r.integer("move_steps", 1, 100'000).value_or(p.move_steps);
    for (const toml::table* prop : r.tables("prop")) {
      TableReader q(*prop, diagnostics, "[[physics.prop]]");
      physics::PropSpec b;
      b.shape = shape(q, "shape").value_or(b.shape);
      if (b.shape == physics::ModuleShape::Cylinder) q.error("shape", "a prop is a \"box\" or a \"sphere\"");
      b.size = vec3(q.numbers("size", 3, 1e-3, 1e3), b.size);
      if (q.has("diameter")) b.size[0] = float(q.number("diameter", 1e-3, 1e3).value_or(1));
      b.mass = float(q.number("mass", 0, 1e9).value_or(b.mass));
      b.pose.position = vec3(q.numbers("position", 3, -kMaxCoordinate, kMaxCoordinate), b.pose.position);
      b.velocity.linear = vec3(q.numbers("velocity", 3, -1e4, 1e4), b.velocity.linear);            // m/s
      b.velocity.angular = vec3(q.numbers("angular_velocity", 3, -1e4, 1e4), b.velocity.angular);  // rad/s
      if (!q.has("position")) q.missing("position");
      q.finish();
      p.props.push_back(b);
    }
    r.finish();
    if (!on) return std::nullopt;
    return p;
  }

  std::optional<std::vector<std::unique_ptr<const sim::HostProgram>>> programs(TableReader& root,
                                                                               const ProgramSetup& setup) {
    const toml::node* n = root.node("program");
    if (!n) {
      root.missing("program");
      return std::nullopt;
    }
    const toml::array* a = n->as_array();
    if (!a || !a->is_array_of_tables() || a->empty()) {
      root.error("program", "'program' must be one or more [[program]] tables");
      return std::nullopt;
    }
    std::vector<std::unique_ptr<const sim::HostProgram>> out;
    bool ok = true;
    for (const toml::node& e : *a) {
      const toml::table& t = *e.as_table();
      TableReader r(t, diagnostics, "[[program]]");
      if (r.has("script")) {
        if (auto program = script_program(r, uint32_t(out.size()))) out.push_back(std::move(program));
        else ok = false;
        continue;
      }
      const auto name = r.string("name");
      if (!name) {
        if (!r.has("name")) r.missing("name");
        ok = false;
        continue;
      }
      const ProgramInfo* info = find_program(*name);
      if (!info) {
        std::string known;
        for (const ProgramInfo& p : builtin_programs()) known += (known.empty() ? "" : ", ") + std::string(p.name);
        r.error("name", "unknown program \"" + *name + "\" (built in: " + known + ")");
        ok = false;
        continue;
      }
      TableReader params(t, diagnostics, "[[program]] " + *name);
      params.node("name");
      auto program = info->make(params, setup);
      params.finish();
      if (!program) ok = false;
      else out.push_back(std::move(program));
    }
    if (!ok) return std::nullopt;
    return out;
  }

  // A file the scenario names, next to it.
  std::string beside(const std::string& name) const {
    return (std::filesystem::path(path).parent_path() / name).string();
  }
  // Its text, counted among the scenario's inputs; nothing, with the error at `key`, when it
  // cannot be read.
  std::optional<std::string> read_beside(TableReader& r, const char* key, const std::string& at, const char* what) {
    inputs.push_back(at);
    std::string error;
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(fifo_deadline - std::chrono::steady_clock::now());
    auto text = sim::read_file(at, &error, sim::kMaxTextInput, true, std::max(left, std::chrono::milliseconds(0)));
    if (!text) r.error(key, error + " (" + what + ")");
    return text;
  }

  // A [[program]] with `script = "x.lua"` (next to the scenario) and the script's parameters.
  std::unique_ptr<const sim::HostProgram> script_program(TableReader& r, uint32_t index) {
    const auto script = r.string("script");
    if (!script) return nullptr;
    if (r.has("name")) {
      r.error("name", "a [[program]] is a built-in program (name) or a script (script), not both");
      return nullptr;
    }
    const std::string at = beside(*script);
    auto text = read_beside(r, "script", at, "the program's script");
    if (!text) return nullptr;
    std::string why;
    ScriptSource source{index, *script, at, {}};
    LuaLimits limits;
    limits.pool = lua_memory;
    auto program = make_lua_program(*script, *text, r, why, limits, &source.params);  // named as the scenario names it
    r.finish();
    if (program) scripts.push_back(std::move(source));
    if (!program && !why.empty()) {
      r.error("script", "the script does not load:");
      extra += why + "\n";
    }
    return program;
  }

  std::optional<watch::Watchpoint> compile(TableReader& r, const std::string& name) {
    const auto text = r.string("text");
    const auto file = r.string("file");
    if (text && file) {
      r.error("file", "a watchpoint takes 'text' or 'file', not both");
      return std::nullopt;
    }
    if (!text && !file) {
      if (!r.has("text") && !r.has("file")) r.missing("text");
      return std::nullopt;
    }
    if (text) {
      const toml::node* value = r.node("text");
      // Compiled in place, so that its diagnostics name the scenario file's line and column.
      if (const auto in_place = text_in_place(diagnostics, *value, *text)) {
        auto compiled = watch::compile_watchpoint(name, watch::SourceText(path, *text, *in_place));
        if (auto* w = std::get_if<watch::Watchpoint>(&compiled)) return std::move(*w);
        for (watch::Diagnostic& d : std::get<watch::CompileError>(compiled).diagnostics) diagnostics.add(std::move(d));
        return std::nullopt;
      }
      auto compiled = watch::compile_watchpoint(name, watch::SourceText(path + " (watch " + name + ")", *text));
      if (auto* w = std::get_if<watch::Watchpoint>(&compiled)) return std::move(*w);
      r.error("text", "the watchpoint does not compile:");
      extra += std::get<watch::CompileError>(compiled).format();
      return std::nullopt;
    }
    // A file next to the scenario.
    const std::string at = beside(*file);
    auto watch_text = read_beside(r, "file", at, "the watchpoint file");
    if (!watch_text) return std::nullopt;
    auto compiled = watch::compile_watchpoint(name, watch::SourceText(at, std::move(*watch_text)));
    if (auto* w = std::get_if<watch::Watchpoint>(&compiled)) return std::move(*w);
    r.error("file", "the watchpoint in " + at + " does not compile:");
    extra += std::get<watch::CompileError>(compiled).format();
    return std::nullopt;
  }

  // [[event]]: at, module, and one of set = { var = value, ... }, remove = true, push = [x, y, z].
  std::vector<sim::Intervention> events(const std::vector<const toml::table*>& tables, const sim::Model& model,
                                        bool physics) {
    std::vector<sim::Intervention> out;
    for (const toml::table* t : tables) {
      TableReader r(*t, diagnostics, "[[event]]");
      const auto at = r.integer("at", 0, kStepsRange.max);
      const auto module = r.integer("module", 0, int64_t{model.module_count()} - 1);
      if (!r.has("at")) r.missing("at");
      if (!r.has("module")) r.missing("module");
      const int kinds = int(r.has("set")) + int(r.has("remove")) + int(r.has("push"));
      if (kinds == 0) {
        diagnostics.add(t->source(), "[[event]] needs one of 'set', 'remove' or 'push'");
        r.finish();
        continue;
      }
      if (kinds > 1) {
        r.error(r.has("push") ? "push" : "remove", "an event does one thing: 'set', 'remove' or 'push'");
        for (const char* key : {"set", "remove", "push"}) r.node(key);
        r.finish();
        continue;
      }
      sim::Intervention base;
      base.at = at.value_or(0);
      base.module = static_cast<sim::ModuleId>(module.value_or(0));
      base.scheduled = true;
      const auto kind = r.has("set")      ? sim::Intervention::Kind::Set
                        : r.has("remove") ? sim::Intervention::Kind::Remove
                                          : sim::Intervention::Kind::Push;
      const std::string empty = module ? sim::empty_cell_problem(model.lattice, base.module, kind) : "";
      if (!empty.empty()) r.error("module", empty);
      const bool ok = at && module && empty.empty();
      if (const toml::table* set = r.has("set") ? r.table("set") : nullptr) {
        if (set->empty()) r.error("set", "'set' names no variable: set = { var = value }");
        for (const auto& [key, value] : *set) {
          const int column = model.column(key.str());
          if (column < 0) {
            diagnostics.add(key.source(), "no program has a variable named \"" + std::string(key.str()) + "\"");
          } else if (!value.is_integer()) {
            diagnostics.add(value.source(), "'" + std::string(key.str()) + "' must be set to an integer");
          } else if (ok) {
            sim::Intervention i = base;
            i.kind = sim::Intervention::Kind::Set;
            i.column = column;
            i.value = value.as_integer()->get();
            out.push_back(i);
          }
        }
      }
      if (r.has("remove")) {
        const auto remove = r.boolean("remove");
        if (remove && !*remove) r.error("remove", "'remove' takes true (leave the key out for no removal)");
        else if (remove && ok)
          out.push_back(
              {.kind = sim::Intervention::Kind::Remove, .at = base.at, .module = base.module, .scheduled = true});
      }
      if (r.has("push")) {
        const auto push = r.numbers("push", 3, -1e9, 1e9);
        if (push && !physics) r.error("push", "a push needs bodies: this scenario has no [physics]");
        else if (push && ok) {
          sim::Intervention i = base;
          i.kind = sim::Intervention::Kind::Push;
          i.impulse = {float((*push)[0]), float((*push)[1]), float((*push)[2])};
          out.push_back(i);
        }
      }
      r.finish();
    }
    return out;
  }

  std::optional<std::vector<sim::HostedWatchpoint>> watches(TableReader& root, const ScenarioOverrides& overrides) {
    std::vector<sim::HostedWatchpoint> out;
    const toml::node* n = root.node("watch");
    if (!n) return out;
    const toml::array* a = n->as_array();
    if (!a || !a->is_array_of_tables()) {
      root.error("watch", "'watch' must be [[watch]] tables");
      return std::nullopt;
    }
    if (a->size() > watch::kMaxWatchpoints) {
      root.error("watch", "a scenario holds at most " + std::to_string(watch::kMaxWatchpoints) + " watchpoints, not " +
                              std::to_string(a->size()));
      return std::nullopt;
    }
    bool ok = true;
    std::vector<std::string> names;
    for (const toml::node& e : *a) {
      TableReader r(*e.as_table(), diagnostics, "[[watch]]");
      const std::optional<std::string> given = r.string("name");  // a wrong type is reported here
      std::string name = given.value_or("");
      if (!r.has("name")) {
        r.missing("name");
        ok = false;
      } else if (!given) {
        ok = false;  // not a string: said by r.string
      } else if (const std::string why = watch::name_problem(name); !why.empty()) {
        r.error("name", why);  // matches, logs and the session's commands name a watchpoint by it
        ok = false;
      } else if (std::find(names.begin(), names.end(), name) != names.end()) {
        r.error("name", "a second watchpoint named \"" + name + "\"");
        ok = false;
      }
      names.push_back(name);
      auto compiled = compile(r, name.empty() ? "watch" : name);
      const auto alg = algorithm(r);
      const auto group = shape(r);
      const auto state_mode = states(r);
      const auto act = action(r);
      const auto max_live = r.integer(kMaxLiveRange);
      const auto early = r.boolean("early_termination");
      const auto cull = r.boolean("neighbor_culling");
      const auto spans = r.boolean("temporal_spans");
      r.finish();
      if (!compiled || (r.has("algorithm") && !alg) || (r.has("shape") && !group) || (r.has("states") && !state_mode) ||
          (r.has("action") && !act) || (r.has("max_live") && !max_live) || (r.has("early_termination") && !early) ||
          (r.has("neighbor_culling") && !cull) || (r.has("temporal_spans") && !spans)) {
        ok = false;
        continue;
      }
      watch::DetectorOptions options;
      options.shape = overrides.shape ? overrides.shape : group;
      options.states = overrides.states ? overrides.states : state_mode;
      const watch::Algorithm chosen = overrides.algorithm.value_or(alg.value_or(watch::Algorithm::Distributed));
      if (const std::string why = watch::unsupported(chosen, options); !why.empty()) {
        // Said at what the file chose; a reading the command line chose in part says so (the
        // user typed --shape, not the line of the file the caret is under).
        std::string typed;
        if (overrides.algorithm) typed += std::string(" --algorithm ") + watch::algorithm_name(*overrides.algorithm);
        if (overrides.shape) typed += std::string(" --shape ") + watch::shape_name(*overrides.shape);
        if (overrides.states) typed += std::string(" --states ") + watch::states_name(*overrides.states);
        const char* key = !overrides.shape && r.has("shape")           ? "shape"
                          : !overrides.states && r.has("states")       ? "states"
                          : !overrides.algorithm && r.has("algorithm") ? "algorithm"
                                                                       : "name";
        r.error(key, typed.empty() ? why : "with" + typed + " from the command line: " + why);
        ok = false;
        continue;
      }
      options.live_budget = overrides.max_live.value_or(static_cast<uint64_t>(max_live.value_or(20'000'000)));
      options.optimizations.early_termination = early.value_or(true);
      options.optimizations.neighbor_culling = cull.value_or(true);
      options.optimizations.temporal_spans = spans.value_or(true);
      out.push_back(sim::HostedWatchpoint{std::move(*compiled), chosen, act.value_or(sim::MatchAction::Log), options});
    }
    if (!ok) return std::nullopt;
    return out;
  }

  std::variant<Scenario, std::string> load(const ScenarioOverrides& overrides) {
    if (const auto at = over_deep_dotted_key(source.text())) {
      diagnostics.add(watch::Diagnostic{{uint32_t(*at), uint32_t(*at + 1)},
                                        "a dotted key of more than " + std::to_string(kMaxKeyParts) +
                                            " parts: tables do not nest that deep in a scenario"});
      return diagnostics.format();
    }
    toml::table doc;
    try {
      doc = toml::parse(std::string_view(source.text()), std::string_view(path));
    } catch (const toml::parse_error& e) {
      diagnostics.add(e.source(), std::string(e.description()));
      return diagnostics.format();
    }
    TableReader root(doc, diagnostics, "the scenario");
    Scenario s;
    s.path = path;
    s.text = source.text();
    s.inputs.push_back(path);
    s.name = root.string("name").value_or(std::filesystem::path(path).stem().string());
    root.string("description");
    const auto steps = root.integer(kStepsRange);
    const auto seed = root.integer(kSeedRange);
    const auto history = root.integer(kHistoryRange);
    const auto threads = root.integer(kThreadsRange);
    s.steps = steps.value_or(100);
    s.history_mb = static_cast<size_t>(history.value_or(256));
    s.threads = static_cast<unsigned>(threads.value_or(1));

    // Whether bodies come with the modules, for the memory estimate ([physics] is read below).
    const bool physics_on = doc["physics"]["enabled"].value_or(false);
    auto built_lattice = lattice(root, overrides, physics_on, s.history_mb);
    std::optional<std::vector<std::unique_ptr<const sim::HostProgram>>> progs;
    if (built_lattice) {
      const ProgramSetup setup{built_lattice->spec, static_cast<uint32_t>(built_lattice->spec.module_count()),
                               built_lattice->occupied};
      progs = programs(root, setup);
    } else {
      root.node("program");  // its errors wait for a lattice
    }
    auto hosted = watches(root, overrides);

    auto physics = physics_settings(root);
    const std::vector<const toml::table*> event_tables = root.tables("event");  // read once the model is
    if (const toml::table* view = root.table("view")) {
      TableReader r(*view, diagnostics, "[view]");
      s.view.color_by = r.string("color_by").value_or("");
      if (auto eye = r.numbers("camera_eye", 3, -kMaxCoordinate, kMaxCoordinate))
        s.view.camera_eye = std::array<double, 3>{(*eye)[0], (*eye)[1], (*eye)[2]};
      if (auto target = r.numbers("camera_target", 3, -kMaxCoordinate, kMaxCoordinate))
        s.view.camera_target = std::array<double, 3>{(*target)[0], (*target)[1], (*target)[2]};
      if (s.view.camera_eye && s.view.camera_target)
        if (std::string problem = camera_problem(*s.view.camera_eye, *s.view.camera_target); !problem.empty())
          r.error("camera_target", problem);
      r.finish();
    }
    root.finish();
    if (!diagnostics.empty() || !extra.empty() || !built_lattice || !progs || !hosted)
      return diagnostics.format() + extra;

    // Now that the programs have said how many variables a module holds (at most the sum of
    // theirs), the estimate again, before the model is built.
    uint64_t variables = 0;
    for (const auto& p : *progs) variables += p->variables().size();
    uint64_t spare = 0;  // what the machine has beyond the estimate; 0: unknown, or not checked
    if (overrides.memory_limit > 0) {
      const uint64_t modules = built_lattice->spec.module_count();
      const uint64_t estimate = memory_estimate(modules, physics_on, s.history_mb, variables);
      if (estimate > overrides.memory_limit) {
        diagnostics.add(doc.get("program")->source(),
                        memory_refusal(modules, physics_on, s.history_mb, overrides.memory_limit, variables));
        return diagnostics.format();
      }
      // What is left is shared: half for the scripts' states (at least what one of them may
      // hold), half for a step's messages, which are kept twice (by the threads that sent them,
      // then as the next step's inbox), so a quarter each time (at least 64 MiB).
      spare = overrides.memory_limit - estimate;
      lua_memory->set_limit(std::max<uint64_t>(spare / 2, LuaLimits{}.memory_bytes));
    }
    auto built = sim::build_model(std::move(*built_lattice), std::move(*progs), std::move(*hosted),
                                  overrides.seed.value_or(static_cast<uint64_t>(seed.value_or(1))));
    if (auto* message = std::get_if<std::string>(&built)) {
      diagnostics.add(doc.get("program")->source(), *message);
      return diagnostics.format();
    }
    s.model = std::move(std::get<std::unique_ptr<sim::Model>>(built));
    if (spare > 0) s.model->message_bytes_per_step = std::max<uint64_t>(spare / 4, uint64_t{64} << 20);
    s.inputs.insert(s.inputs.end(), inputs.begin(), inputs.end());
    s.scripts = std::move(scripts);
    s.lua_memory = lua_memory;
    // A variable no program has would read as unknown forever: the watchpoint could never match.
    // The error points at the variable where it is first read, in the scenario or the watch file.
    for (size_t w = 0; w < s.model->watches.size(); ++w) {
      const watch::Watchpoint& wp = s.model->watches[w].watchpoint;
      for (const std::string& v : wp.program.variables) {
        if (s.model->column(v) >= 0) continue;
        std::string known;
        for (const std::string& k : s.model->universe.variables) known += (known.empty() ? "" : ", ") + k;
        const std::string message =
            "watchpoint \"" + wp.name + "\" reads '" + v + "', which no program has (variables: " + known + ")";
        const watch::Span at = watch::first_use(wp.ast, v);
        if (wp.source->name() == path) {
          diagnostics.add({at, message});  // compiled in place: the span is the scenario file's
        } else {
          TableReader r(*(*doc.get("watch")->as_array())[w].as_table(), diagnostics, "[[watch]]");
          r.error(r.has("text") ? "text" : "file", message + ":");
          extra += watch::format_diagnostic(*wp.source, {at, "'" + v + "' is read here"});
        }
      }
    }
    if (!diagnostics.empty()) return diagnostics.format() + extra;
    if (!s.view.color_by.empty() && s.model->column(s.view.color_by) < 0) {
      TableReader r(*doc.get("view")->as_table(), diagnostics, "[view]");
      r.error("color_by", "no program has a variable named \"" + s.view.color_by + "\"");
      return diagnostics.format();
    }
    s.events = events(event_tables, *s.model, physics.has_value());
    if (!diagnostics.empty()) return diagnostics.format();
    if (physics) s.world = std::make_unique<physics::BulletWorld>(std::move(*physics), s.model->lattice);
    else s.world = std::make_unique<sim::StaticLatticeWorld>();
    return s;
  }
};

}  // namespace

std::variant<Scenario, std::string> load_scenario_text(const std::string& path, std::string text,
                                                       const ScenarioOverrides& overrides) {
  Loader loader(path, std::move(text));
  return loader.load(overrides);
}

std::variant<Scenario, std::string> load_scenario(const std::string& path, const ScenarioOverrides& overrides) {
  std::string error;
  auto text = sim::read_file(path, &error);
  if (!text) return path + ": error: " + error + " (the scenario file)\n";
  return load_scenario_text(path, std::move(*text), overrides);
}

std::variant<std::vector<std::string>, std::string> reload_scripts(const Scenario& scenario, sim::Session& session) {
  std::vector<sim::Session::Replacement> loaded;
  std::vector<std::string> names;
  for (const ScriptSource& source : scenario.scripts) {
    std::string why;
    auto text = sim::read_file(source.file, &why);
    if (!text) return why;
    LuaLimits limits;
    limits.pool = scenario.lua_memory;
    std::shared_ptr<const sim::HostProgram> program =
        make_lua_program(source.display, *text, source.params, why, limits);
    if (!program) return why;
    names.emplace_back(program->name());
    loaded.push_back({source.program, std::move(program)});
  }
  if (std::string why = session.replace_programs(std::move(loaded)); !why.empty()) return why;
  return names;
}

std::string camera_problem(std::span<const double> eye, std::span<const double> target) {
  for (std::span<const double> v : {eye, target})
    for (double c : v)
      if (!std::isfinite(c) || std::abs(c) > kMaxCoordinate)
        return "a camera coordinate must be a finite number from -1e6 to 1e6, not " + std::to_string(c);
  // On its target, or so near that no direction can be told (the renderer would draw the fitted
  // view instead, render::make_camera): a millionth of the eye's distance from the origin.
  if (eye.size() == 3 && target.size() == 3 &&
      std::hypot(eye[0] - target[0], eye[1] - target[1], eye[2] - target[2]) <=
          1e-6 * std::max(1.0, std::hypot(eye[0], eye[1], eye[2])))
    return "the camera's eye is on its target, so it looks nowhere: move one of them";
  return "";
}

}  // namespace dw::scenarios
