// The scenario loader's state, shared by its files and private to them (scenarios/scenario.h is the
// loader's interface). scenario.cpp reads the file's top level and calls one function per section,
// each in a file of its own: scenario_lattice.cpp [lattice], scenario_physics.cpp [physics],
// scenario_programs.cpp [[program]], scenario_watches.cpp [[watch]], scenario_events.cpp [[event]]
// and scenario_view.cpp [view]. Every mistake goes to `diagnostics` (or, against another file, to
// `extra`), in the order the file is read: the order of the calls in Loader::load.
#pragma once

#include <toml++/toml.h>

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "physics/settings.h"
#include "scenarios/lua_host/lua_memory_pool.h"
#include "scenarios/programs/programs.h"
#include "scenarios/scenario.h"
#include "scenarios/table_reader.h"
#include "sim/lattice.h"
#include "sim/read_file.h"
#include "watch/watchpoint.h"

namespace dw::scenarios {

struct Loader {
  std::string path;
  watch::SourceText source;
  FileDiagnostics diagnostics{source};
  std::string extra;                // diagnostics rendered against other files (watchpoint files)
  std::vector<std::string> inputs;  // the files read besides the scenario (watchpoint files)
  std::vector<ScriptSource> scripts;
  // What the scripts' Lua states may hold together (Scenario::lua_memory).
  const std::shared_ptr<LuaMemoryPool> lua_memory = std::make_shared<LuaMemoryPool>();
  // The files it names that are FIFOs share one wait: a scenario naming the same FIFO a thousand
  // times holds dwatch no longer than one naming it once.
  const std::chrono::steady_clock::time_point fifo_deadline = std::chrono::steady_clock::now() + sim::kFifoWriterWait;

  Loader(std::string p, std::string text) : path(p), source(std::move(p), std::move(text)) {}

  // The whole file, section by section (scenario.cpp).
  std::variant<Scenario, std::string> load(const ScenarioOverrides& overrides);
  // A file the scenario names, next to it.
  std::string beside(const std::string& name) const;
  // Its text, counted among the scenario's inputs; nothing, with the error at `key`, when it
  // cannot be read.
  std::optional<std::string> read_beside(TableReader& r, const char* key, const std::string& at, const char* what);

  // [lattice] (scenario_lattice.cpp).
  std::optional<sim::Lattice> lattice(TableReader& root, const ScenarioOverrides& overrides, bool physics,
                                      uint64_t history_mb);
  // [physics] (scenario_physics.cpp).
  std::optional<physics::PhysicsSettings> physics_settings(TableReader& root);
  // [[program]] (scenario_programs.cpp).
  std::optional<std::vector<std::unique_ptr<const sim::HostProgram>>> programs(TableReader& root,
                                                                               const ProgramSetup& setup,
                                                                               const ProvidedPrograms& python);
  std::unique_ptr<const sim::HostProgram> script_program(TableReader& r, uint32_t index);
  std::unique_ptr<const sim::HostProgram> python_program(const toml::table& t, const ProvidedPrograms& python);
  // [[watch]] (scenario_watches.cpp).
  std::optional<std::vector<sim::HostedWatchpoint>> watches(TableReader& root, const ScenarioOverrides& overrides);
  std::optional<watch::Watchpoint> compile(TableReader& r, const std::string& name);
  void check_watched_variables(const sim::Model& model, const toml::table& doc);
  // [[event]] (scenario_events.cpp).
  std::vector<sim::Intervention> events(const std::vector<const toml::table*>& tables, const sim::Model& model,
                                        bool physics);
  // [[bookmark]] (scenario_events.cpp).
  std::vector<sim::Bookmark> bookmarks(const std::vector<const toml::table*>& tables);
  // [view] (scenario_view.cpp).
  void view(TableReader& root, ViewSettings& out);
  bool check_color_by(const ViewSettings& view, const sim::Model& model, const toml::table& doc);
};

}  // namespace dw::scenarios
