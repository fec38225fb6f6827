// Scenario files (scenarios/scenario.h): the entry points and the file's top level (name, steps,
// seed, history_mb, threads), read before and around its sections, each of which has a file of
// its own (scenarios/scenario_loader.h lists them).
#include "scenarios/scenario.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>

#include "physics/bullet_world.h"
#include "scenarios/lua_host/lua_program.h"
#include "scenarios/memory_estimate.h"
#include "scenarios/scenario_loader.h"
#include "sim/read_file.h"

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

}  // namespace

std::string Loader::beside(const std::string& name) const {
  return (std::filesystem::path(path).parent_path() / name).string();
}

std::optional<std::string> Loader::read_beside(TableReader& r, const char* key, const std::string& at,
                                               const char* what) {
  // A TOML string may hold "\u0000", which no file name can: the system would read the path as
  // cut short at it, another file than the one named.
  if (at.find('\0') != std::string::npos) {
    r.error(key, std::string("the path holds a NUL byte (\\u0000), which no file name can (") + what + ")");
    return std::nullopt;
  }
  inputs.push_back(at);
  std::string error;
  const auto left =
      std::chrono::duration_cast<std::chrono::milliseconds>(fifo_deadline - std::chrono::steady_clock::now());
  auto text = sim::read_file(at, &error, sim::kMaxTextInput, true, std::max(left, std::chrono::milliseconds(0)));
  if (!text) r.error(key, error + " (" + what + ")");
  return text;
}

std::variant<Scenario, std::string> Loader::load(const ScenarioOverrides& overrides) {
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
    progs = programs(root, setup, overrides.python_programs);
  } else {
    root.node("program");  // its errors wait for a lattice
  }
  auto hosted = watches(root, overrides);

  auto physics = physics_settings(root);
  const std::vector<const toml::table*> event_tables = root.tables("event");  // read once the model is built
  s.bookmarks = bookmarks(root.tables("bookmark"));
  view(root, s.view);
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
  check_watched_variables(*s.model, doc);
  if (!diagnostics.empty()) return diagnostics.format() + extra;
  if (!check_color_by(s.view, *s.model, doc)) return diagnostics.format();
  s.events = events(event_tables, *s.model, physics.has_value());
  if (!diagnostics.empty()) return diagnostics.format();
  if (physics) s.world = std::make_unique<physics::BulletWorld>(std::move(*physics), s.model->lattice);
  else s.world = std::make_unique<sim::StaticLatticeWorld>();
  return s;
}

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

}  // namespace dw::scenarios
