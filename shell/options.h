// What `dwatch session`, `dwatch view` and the Python package take besides their own options to
// start a session: the scenario, and what may override it.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>

#include "scenarios/scenario.h"
#include "sim/session.h"

namespace dw::shell {

struct SessionSource {
  std::string scenario;
  std::optional<int64_t> seed, threads, history_mb, max_live_all, lua_seconds;
  bool no_memory_check = false;
};
// Registers --no-memory-check, which loads a scenario whose memory estimate is above what the
// machine has (scenarios/memory_estimate.h), on a command that loads one.
void add_memory_check_flag(CLI::App& cmd, bool& off);
// The limit a scenario's estimate is checked against: the machine's, or none when `off`.
uint64_t memory_limit_unless(bool off);
// Registers the scenario argument and --seed, --threads, --history-mb, --max-live-all, --lua-seconds
// on a subcommand.
void add_session_source(CLI::App& cmd, SessionSource& source);
// The scenario with the overrides, or nothing (its diagnostics printed on stderr).
std::optional<scenarios::Scenario> load_session_scenario(const SessionSource& source);
// The session's settings: the scenario's, with the overrides.
sim::SessionOptions session_options(const scenarios::Scenario& scenario, const SessionSource& source);

}  // namespace dw::shell
