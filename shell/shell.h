// The session command language (docs/design.md §7a): one command a line, `#` comments, each answered
// with one JSON object a line. `dwatch session` reads it from a script or a prompt; the window
// sends the same commands. This file only parses and formats: every decision (where a run stops,
// what an intervention drops, what a view of a step shows) is the session's (sim/session.h).
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "render/scene.h"
#include "scenarios/scenario.h"
#include "sim/session.h"
#include "watch/diagnostic.h"

namespace dw::app {

struct SessionCommand {
  enum class Kind {
    Step,
    Run,
    Continue,
    Seek,
    Set,
    Remove,
    Push,
    Watch,
    Unwatch,
    Action,
    Matches,
    State,
    Hash,
    Render,
    Record,
    Save,
    Interventions,
    Reload,
    Status,
    Help,
  };
  Kind kind = Kind::Help;
  uint32_t line = 0;              // in the script
  std::optional<int64_t> number;  // step N, run T, seek T, matches T
  std::string name;               // watch/unwatch/action/matches NAME, run --to-match NAME, render/record/save FILE
  sim::MatchAction action = sim::MatchAction::Log;  // action NAME ACTION
  bool overwrite = false;                           // save FILE overwrite
  int width = 1280, height = 720;                   // render
  std::optional<sim::Intervention> intervention;
  std::optional<sim::HostedWatchpoint> watch;
};

// What `dwatch session` and `dwatch view` take besides their own options: the scenario, and
// what may override it.
struct SessionSource {
  std::string scenario;
  std::optional<int64_t> seed, threads, history_mb;
  bool no_memory_check = false;
};
// Registers --no-memory-check, which loads a scenario whose memory estimate is above what the
// machine has (scenarios/memory_estimate.h), on a command that loads one.
void add_memory_check_flag(CLI::App& cmd, bool& off);
// The limit a scenario's estimate is checked against: the machine's, or none when `off`.
uint64_t memory_limit_unless(bool off);
// Registers the scenario argument and --seed, --threads, --history-mb on a subcommand.
void add_session_source(CLI::App& cmd, SessionSource& source);
// The scenario with the overrides, or nothing (its diagnostics printed on stderr).
std::optional<scenarios::Scenario> load_session_scenario(const SessionSource& source);
// The session's settings: the scenario's, with the overrides.
sim::SessionOptions session_options(const scenarios::Scenario& scenario, const SessionSource& source);

// A mistake for each variable the watchpoint reads that no program of the model has.
std::vector<watch::Diagnostic> unknown_variables(const sim::Model& model, const watch::Watchpoint& watchpoint);

// `word` as one word of a command line: in double quotes when it holds a space or a '#' (a file's
// name; one holding a double quote cannot be said).
std::string session_word(const std::string& word);

// The commands, one line each, as `help` answers them.
const std::vector<std::string>& session_command_help();

class SessionShell {
 public:
  // `scenario` gives the model the commands are checked against (its variables, modules, physics)
  // and the files they must not overwrite.
  SessionShell(const scenarios::Scenario& scenario, sim::Session& session);

  // Parses the line of `source` that starts at byte `begin` (1-based number `line`). Nothing for
  // a blank or comment line; the diagnostics (one per mistake) when it is wrong.
  std::variant<std::optional<SessionCommand>, std::vector<watch::Diagnostic>> parse(const watch::SourceText& source,
                                                                                    uint32_t begin, uint32_t line);

  // Carries a command out: its answer, or why it failed.
  std::variant<nlohmann::ordered_json, std::string> execute(const SessionCommand& command,
                                                            const sim::Control& control = {});

  // The 3D view of the current step (step 0 before any), its first match of each watchpoint
  // highlighted: what `render` draws.
  render::Scene scene();

  // Match i of watchpoint w as a line of the match log (docs/design.md §5).
  nlohmann::ordered_json match_json(uint32_t w, size_t i) const;

 private:
  nlohmann::ordered_json position();

  const scenarios::Scenario& scenario_;
  sim::Session& session_;
};

}  // namespace dw::app
