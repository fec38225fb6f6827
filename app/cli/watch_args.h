// Watchpoints given on the command line: `TEXT`, `@FILE`, `NAME=TEXT` or `NAME=@FILE`.
#pragma once

#include <string>
#include <variant>
#include <vector>

#include "watch/watchpoint.h"

namespace dw::app {

// Compiles every watchpoint; on any error returns the rendered diagnostics of all of them.
std::variant<std::vector<watch::Watchpoint>, std::string> load_watchpoints(
    const std::vector<std::string>& args, std::vector<std::string>* files_read = nullptr);

}  // namespace dw::app
