// The session command language (docs/design.md §7a): one command a line, `#` comments, each answered
// with one JSON object a line. `dwatch session` reads it from a script or a prompt; the window
// sends the same commands. This file only parses and formats: every decision (where a run stops,
// what an intervention drops, what a view of a step shows) is the session's (sim/session.h).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <variant>
#include <vector>

#include "render/scene.h"
#include "scenarios/scenario.h"
#include "shell/command.h"
#include "sim/session.h"
#include "watch/diagnostic.h"

namespace dw::shell {

class Shell {
 public:
  // `scenario` gives the model the commands are checked against (its variables, modules, physics)
  // and the files they must not overwrite.
  Shell(const scenarios::Scenario& scenario, sim::Session& session);

  // Parses the line of `source` that starts at byte `begin` (1-based number `line`). Nothing for
  // a blank or comment line; the diagnostics (one per mistake) when it is wrong.
  std::variant<std::optional<Command>, std::vector<watch::Diagnostic>> parse(const watch::SourceText& source,
                                                                                    uint32_t begin, uint32_t line);

  // Carries a command out: its answer, or why it failed.
  std::variant<nlohmann::ordered_json, std::string> execute(const Command& command,
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

}  // namespace dw::shell
