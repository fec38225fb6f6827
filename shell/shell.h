// The session command language (docs/design.md §7a): one command a line, `#` comments, each answered
// with one JSON object a line. `dwatch session` reads it from a script or a prompt; the window
// sends the same commands. The shell only parses and formats: every decision (where a run stops,
// what an intervention drops, what a view of a step shows) is the session's (sim/session.h).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "render/scene.h"
#include "scenarios/scenario.h"
#include "shell/command.h"
#include "sim/bookmarks.h"
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
  std::variant<nlohmann::ordered_json, std::string> execute(const Command& command, const sim::Control& control = {});

  // The 3D view of the current step (step 0 before any), its first match of each watchpoint
  // highlighted: what `render` draws.
  render::Scene scene();

  // The bookmarks (`mark`), the scenario's [[bookmark]]s first.
  const sim::Bookmarks& bookmarks() const { return bookmarks_; }

  // Match i of watchpoint w as a line of the match log (docs/design.md §5).
  nlohmann::ordered_json match_json(uint32_t w, size_t i) const;

 private:
  using Answer = std::variant<nlohmann::ordered_json, std::string>;

  // The commands, each given its answer begun (its "cmd") to go on with. carry_out.cpp: those
  // that move the session or change its watchpoints; answers.cpp: those that only read it;
  // write_files.cpp: those that write a file.
  Answer run_to(const Command& command, const sim::Control& control, nlohmann::ordered_json answer);
  Answer seek(const Command& command, const sim::Control& control, nlohmann::ordered_json answer);
  Answer find(const Command& command, const sim::Control& control, nlohmann::ordered_json answer);
  Answer eval(const Command& command, const sim::Control& control, nlohmann::ordered_json answer);
  Answer bookmark(const Command& command, nlohmann::ordered_json answer);
  Answer diff(const Command& command, const sim::Control& control, nlohmann::ordered_json answer);
  Answer intervene(const Command& command, nlohmann::ordered_json answer);
  Answer reload(nlohmann::ordered_json answer);
  Answer set_watch(const Command& command, const sim::Control& control, nlohmann::ordered_json answer);
  Answer set_action(const Command& command, nlohmann::ordered_json answer);
  Answer matches(const Command& command, nlohmann::ordered_json answer);
  Answer module_state(const Command& command, nlohmann::ordered_json answer);
  Answer state_hash(nlohmann::ordered_json answer);
  Answer interventions(nlohmann::ordered_json answer);
  Answer status(nlohmann::ordered_json answer);
  Answer render_file(const Command& command, const sim::Control& control, nlohmann::ordered_json answer);
  Answer record_file(const Command& command, const sim::Control& control, nlohmann::ordered_json answer);
  Answer save_file(const Command& command, nlohmann::ordered_json answer);

  // A command's failure, and why.
  static Answer failed(std::string why) { return Answer(std::in_place_index<1>, std::move(why)); }
  // Where the cursor stands: current, latest and decided steps, added to an answer.
  void add_position(nlohmann::ordered_json& answer);
  nlohmann::ordered_json intervention_answer(const sim::Intervention& intervention) const;
  // Why watchpoint w stopped (it has), as `dwatch run` says it: the reason, its figure, the matches
  // kept and the option that raises the budget.
  std::string stop_reason(uint32_t w) const;

  const scenarios::Scenario& scenario_;
  sim::Session& session_;
  sim::Bookmarks bookmarks_;
};

}  // namespace dw::shell
