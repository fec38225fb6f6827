// Watchpoints given on the command line: `TEXT`, `@FILE`, `NAME=TEXT` or `NAME=@FILE`.
#pragma once

#include <string>
#include <variant>
#include <vector>

#include "sim/watch_spec.h"

namespace dw::app {

// Compiles every watchpoint, each with `reading` (the command's flags); on any error returns the
// rendered diagnostics of all of them.
std::variant<std::vector<sim::HostedWatchpoint>, std::string> load_watchpoints(
    const std::vector<std::string>& args, const sim::WatchSpec& reading = {},
    std::vector<std::string>* files_read = nullptr);

}  // namespace dw::app
