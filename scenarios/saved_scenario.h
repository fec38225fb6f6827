// A session saved as a scenario file (`save FILE` in the session language, "Save as scenario" in
// the window; docs/design.md §7a): loaded again, it runs the branch the session stands on.
#pragma once

#include <optional>
#include <string>

#include "scenarios/scenario.h"
#include "sim/session.h"

namespace dw::scenarios {

// The scenario's own text made into the session's: its settings as the file gives them, with
//   - the session's watchpoints in place of the file's (each with its reading, action, budget
//     and optimizations: those added, replaced or removed in the session included);
//   - every intervention of the branch, scheduled or made, as [[event]] tables;
//   - the session's bookmarks as [[bookmark]] tables;
//   - the seed the session runs with;
//   - each relative path (a program's `script`) rewritten for a file at `destination`, so that
//     the saved scenario runs from any working directory.
// Comments of the original do not survive (the file is written anew from its tables); a header
// says where it came from. Nothing, with `error` set, when the text cannot be made.
std::optional<std::string> saved_scenario(const Scenario& scenario, const sim::Session& session,
                                          const sim::Bookmarks& bookmarks, const std::string& destination,
                                          std::string* error);

}  // namespace dw::scenarios
