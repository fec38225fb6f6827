// A named, checked and compiled watchpoint: the one object the detectors are built from.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "watch/analysis.h"
#include "watch/ast.h"
#include "watch/diagnostic.h"
#include "watch/program.h"
#include "watch/source.h"
#include "watch/windows.h"

namespace dw::watch {

// Watchpoints one run may hold (a scenario, a trace's header, a session, the command line). Each
// keeps its detector, history and statistics: 100,000 of them, a 5 MB scenario, took 2.5 GB.
inline constexpr size_t kMaxWatchpoints = 1000;

struct Watchpoint {
  std::string name;
  std::shared_ptr<const SourceText> source;
  Ast ast;
  Analysis analysis;
  Program program;
};

struct CompileError {
  std::shared_ptr<const SourceText> source;
  std::vector<Diagnostic> diagnostics;
  std::string format() const { return format_diagnostics(*source, diagnostics); }
};

// Why `name` cannot name a watchpoint, or empty when it can. Matches, logs and the session's
// commands name a watchpoint by it, so it is a word they can say: not empty, no control
// character (nothing a terminal or a log shows), not starting with a double quote (the session
// reads a quoted word as the word inside), and not an integer (`matches 12` is step 12).
std::string name_problem(std::string_view name);

// Parses, checks and compiles. Never throws on bad input: errors come back as diagnostics.
std::variant<Watchpoint, CompileError> compile_watchpoint(std::string name, SourceText source,
                                                          WindowKeeping keeping = WindowKeeping::ByModule);

}  // namespace dw::watch
