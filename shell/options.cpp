#include "shell/options.h"

#include <iostream>

#include "scenarios/limits.h"
#include "scenarios/memory_estimate.h"
#include "shell/integer_option.h"

namespace dw::shell {

void add_session_source(CLI::App& cmd, SessionSource& source) {
  cmd.add_option("scenario", source.scenario, "Scenario file (TOML)")->required();
  add_integer_option(cmd, "--seed", source.seed, scenarios::kSeedRange, "Random seed (default: the scenario's)");
  add_integer_option(cmd, "--threads,-j", source.threads, scenarios::kThreadsRange,
                     "Threads stepping modules (results never depend on it)");
  add_integer_option(cmd, "--history-mb", source.history_mb, scenarios::kHistoryRange,
                     "Memory for the history's keyframes, in MiB (default: the scenario's)");
  add_integer_option(cmd, "--max-live-all", source.max_live_all, scenarios::kMaxLiveRange,
                     "Budget of all watchpoints together: most PatternMatchers alive in one step (0: none)")
      ->default_val(sim::kDefaultRunBudget);
  add_integer_option(cmd, "--lua-seconds", source.lua_seconds, scenarios::kLuaSecondsRange,
                     "Wall-clock seconds all the Lua calls may take together, besides 10 s a call (0: none)")
      ->default_val(scenarios::LuaMemoryPool::kDefaultSeconds);
  add_memory_check_flag(cmd, source.no_memory_check);
}

void add_memory_check_flag(CLI::App& cmd, bool& off) {
  cmd.add_flag("--no-memory-check", off,
               "Load the scenario even when its memory estimate is above what this machine has available");
}

uint64_t memory_limit_unless(bool off) { return off ? 0 : scenarios::memory_limit(); }

std::optional<scenarios::Scenario> load_session_scenario(const SessionSource& source) {
  scenarios::ScenarioOverrides overrides;
  if (source.seed) overrides.seed = static_cast<uint64_t>(*source.seed);
  overrides.memory_limit = memory_limit_unless(source.no_memory_check);
  auto loaded = scenarios::load_scenario(source.scenario, overrides);
  if (auto* errors = std::get_if<std::string>(&loaded)) {
    std::cerr << *errors;
    return std::nullopt;
  }
  scenarios::Scenario& scenario = std::get<scenarios::Scenario>(loaded);
  if (source.lua_seconds) scenario.lua_memory->set_seconds(*source.lua_seconds);
  return std::move(scenario);
}

sim::SessionOptions session_options(const scenarios::Scenario& scenario, const SessionSource& source) {
  return {
      .threads = source.threads ? static_cast<unsigned>(*source.threads) : scenario.threads,
      .end = scenario.steps,
      .history_bytes = (source.history_mb ? static_cast<size_t>(*source.history_mb) : scenario.history_mb) << 20,
      .events = scenario.events,
      .run_live_budget = source.max_live_all ? static_cast<uint64_t>(*source.max_live_all) : sim::kDefaultRunBudget};
}

}  // namespace dw::shell
