// Scenario files (docs/design.md §5): a TOML description of an ensemble, its programs, its watchpoints and
// how to run and show it, loaded into a Model and a World. Every mistake in the file is reported
// as `file:line:col: error: message` with the line and a caret; nothing is thrown.
//
//   name = "leader_election"          # default: the file's stem
//   steps = 200                        # default 100
//   seed = 1                           # default 1
//   history_mb = 256                   # memory for the session's keyframes (default 256 MiB)
//   threads = 1                        # default 1
//   [lattice]                          # required
//   kind = "hex2d"                     # cubic | square2d | hex2d | ring | line
//   size = [12, 10]                    # 3, 2 or 1 sizes
//   [[program]]                        # one or more, run side by side
//   name = "leader_election"           # plus the program's own parameters
//   bug = true
//   [[watch]]                          # zero or more
//   name = "two_leaders"
//   text = "modules(a b c); (a.isLeader = 1) and (c.isLeader = 1)"   # or file = "x.watch"
//   algorithm = "distributed"          # or centralized (default distributed)
//   shape = "chain"                    # chain | ordered | any (docs/design.md §4a; default: ordered
//                                      # centralized, chain distributed)
//   states = "simultaneous"            # distributed: consistent (the paper's) | simultaneous
//   action = "pause"                   # pause | log | count (default log)
//   max_live = 20000000                # the PatternMatcher budget (0: none; default sim::kDefaultMatchBudget)
//   early_termination = true           # the §IV optimizations, all on by default
//   neighbor_culling = true
//   temporal_spans = true
//   [[lattice.empty]]                  # cells left empty (inclusive lattice coordinates)
//   from = [x, y, z]
//   to = [x, y, z]
//   [physics]                          # a Bullet world (docs/design.md §8); off: the static lattice
//   enabled = false
//   dt = 0.0166667                     # seconds per step
//   gravity = [0, 0, -9.81]
//   shape = "box"                      # box | cylinder | sphere (default: by lattice kind)
//   module_mass = 1
//   contact_threshold = 0.01           # neighbours when at most this far apart (<= 0.015)
//   bonds = true                       # latch modules touching at the start
//   anchor = true                      # latch modules touching the ground to it
//   break_force = 1000                 # newtons; a module pushed harder loses its bonds (0: never)
//   friction = 0.6
//   restitution = 0.1
//   rolling_friction = 0.02            # m: a round module's rolling resistance (a lever)
//   spinning_friction = 0.02           # m: and against spinning about a contact's normal
//   solver_iterations = 10
//   substeps = 4                       # each step solved as this many substeps
//   sleep_after = 2                    # seconds still before a free body sleeps (0: never)
//   move_steps = 30                    # steps a lattice move takes
//   [[physics.prop]]                   # bodies that are not modules: projectiles, obstacles
//   shape = "sphere"                   # sphere | box
//   diameter = 1.5                     # a sphere's; a box has size = [x, y, z]
//   mass = 40                          # 0: fixed in place
//   position = [x, y, z]
//   velocity = [x, y, z]
//   [[event]]                          # interventions scheduled at the start of step `at` (docs/design.md §7)
//   at = 40
//   module = 7
//   set = { token = 1 }                # or remove = true, or push = [x, y, z] (physics: N s)
//   [[bookmark]]                       # a note on a step, on the window's timeline (docs/view.md)
//   at = 40
//   note = "the second leader appears"
//   [view]
//   color_by = "isLeader"
//   camera_eye = [x, y, z]             # default: fitted to the ensemble
//   camera_target = [x, y, z]
#pragma once

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <variant>

#include "scenarios/lua_host/lua_memory_pool.h"
#include "sim/bookmarks.h"
#include "sim/intervention.h"
#include "sim/model.h"
#include "sim/session.h"
#include "sim/world.h"

namespace dw::scenarios {

struct ViewSettings {
  std::string color_by;  // a variable name, or empty
  std::optional<std::array<double, 3>> camera_eye, camera_target;
};

// A [[program]] read from a script: what loading it again takes.
struct ScriptSource {
  uint32_t program = 0;                                 // its index in the model's programs
  std::string display;                                  // the script as the scenario names it
  std::string file;                                     // where it is
  std::vector<std::pair<std::string, int64_t>> params;  // the values the scenario gives it
};

struct Scenario {
  std::string path;
  std::string text;                 // the file as it was read (for saving a session as a scenario)
  std::vector<std::string> inputs;  // every file it was read from: the scenario, watchpoint files
  std::string name;
  std::unique_ptr<sim::Model> model;
  std::unique_ptr<sim::World> world;
  int64_t steps = 100;
  size_t history_mb = 256;
  std::vector<sim::Intervention> events;  // [[event]], in file order
  std::vector<sim::Bookmark> bookmarks;   // [[bookmark]], in file order
  unsigned threads = 1;
  ViewSettings view;
  std::vector<ScriptSource> scripts;
  // What the scripts' Lua states may hold together, shared by those reloaded.
  std::shared_ptr<LuaMemoryPool> lua_memory = std::make_shared<LuaMemoryPool>();
};

// Loads the scenario's scripts again from their files (they changed) and runs each in place of
// its old self from the step after the session's current one, on a new branch
// (sim::Session::replace_programs). The scripts reloaded, or the first reason one cannot be (a
// mistake in it, a parameter it no longer declares, other variables): then nothing changed.
std::variant<std::vector<std::string>, std::string> reload_scripts(const Scenario& scenario, sim::Session& session);

class TableReader;
// A host program written in Python that the caller of the loader gives by name (Python's
// `dwatch.Session(scenario, programs={"mine": Mine})`), which a [[program]] names with
// `python = "mine"`: built with that table's parameters (mistakes reported there); nullptr when
// one was wrong.
using ProvidedProgram = std::function<std::unique_ptr<const sim::HostProgram>(TableReader& params)>;
using ProvidedPrograms = std::map<std::string, ProvidedProgram, std::less<>>;

// Command-line settings that win over the file's.
struct ScenarioOverrides {
  std::optional<uint64_t> seed;
  std::optional<watch::Algorithm> algorithm;
  std::optional<watch::GroupShape> shape;
  std::optional<watch::States> states;
  std::optional<uint64_t> max_live;    // every watchpoint's PatternMatcher budget
  uint64_t max_modules = 100'000'000;  // the largest lattice accepted (a fuzzer asks for less)
  // Refuse a scenario whose memory estimate (scenarios/memory_estimate.h) is above this many
  // bytes, before allocating it; 0: no check. The command line gives the machine's memory_limit().
  uint64_t memory_limit = 0;
  // The Python programs given, by name: a scenario naming one not given is refused (Python code
  // runs only when its user passes it in).
  ProvidedPrograms python_programs;
};

// The scenario, or the rendered diagnostics.
std::variant<Scenario, std::string> load_scenario(const std::string& path, const ScenarioOverrides& overrides = {});

// Coordinates a scenario or the command line may give (positions, the camera), in module sizes.
inline constexpr double kMaxCoordinate = 1e6;
// What is wrong with a camera a user typed (a coordinate not finite or out of range, an eye on
// its target), or "" when it can be drawn.
std::string camera_problem(std::span<const double> eye, std::span<const double> target);
std::variant<Scenario, std::string> load_scenario_text(const std::string& path, std::string text,
                                                       const ScenarioOverrides& overrides = {});

}  // namespace dw::scenarios
