// A scenario's [[program]] tables: a built-in program by name with its parameters
// (scenarios/programs/), or a script in Lua next to the scenario (scenarios/lua_host/), and the
// scripts loaded again when they change.
#include "scenarios/lua_host/lua_program.h"
#include "scenarios/scenario_loader.h"

namespace dw::scenarios {

// [[program]]: one or more, run side by side; each a built-in program (`name` and its parameters),
// a script (`script` and its parameters) or a Python program given by the caller (`python` and its
// parameters).
std::optional<std::vector<std::unique_ptr<const sim::HostProgram>>> Loader::programs(TableReader& root,
                                                                                     const ProgramSetup& setup,
                                                                                     const ProvidedPrograms& python) {
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
    if (r.has("python")) {
      if (auto program = python_program(t, python)) out.push_back(std::move(program));
      else ok = false;
      continue;
    }
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

// A [[program]] with `script = "x.lua"` (next to the scenario) and the script's parameters.
std::unique_ptr<const sim::HostProgram> Loader::script_program(TableReader& r, uint32_t index) {
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

// A [[program]] with `python = "NAME"`: the program the caller gave by that name, with the table's
// parameters. Only the caller's own code runs: a name it did not give is refused.
std::unique_ptr<const sim::HostProgram> Loader::python_program(const toml::table& t, const ProvidedPrograms& python) {
  TableReader r(t, diagnostics, "[[program]]");
  const auto name = r.string("python");
  if (!name) return nullptr;
  if (r.has("name") || r.has("script")) {
    r.error(r.has("name") ? "name" : "script",
            "a [[program]] is a built-in program (name), a script (script) or a Python program (python), not two");
    return nullptr;
  }
  const auto it = python.find(*name);
  if (it == python.end()) {
    std::string given;
    for (const auto& [known, make] : python) given += (given.empty() ? "" : ", ") + known;
    r.error("python", given.empty() ? "the Python program \"" + *name +
                                          "\" is not given: a scenario naming a Python program runs from Python, "
                                          "with dwatch.Session(scenario, programs={\"" +
                                          *name + "\": ...})"
                                    : "no Python program \"" + *name + "\" is given (given: " + given + ")");
    return nullptr;
  }
  TableReader params(t, diagnostics, "[[program]] " + *name);
  params.node("python");
  auto program = it->second(params);
  params.finish();
  return program;
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

}  // namespace dw::scenarios
