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
  return std::move(std::get<scenarios::Scenario>(loaded));
}

sim::SessionOptions session_options(const scenarios::Scenario& scenario, const SessionSource& source) {
  return {.threads = source.threads ? static_cast<unsigned>(*source.threads) : scenario.threads,
          .end = scenario.steps,
          .history_bytes = (source.history_mb ? static_cast<size_t>(*source.history_mb) : scenario.history_mb) << 20,
          .events = scenario.events};
}

}  // namespace dw::shell
