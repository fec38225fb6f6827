// A named, checked and compiled watchpoint: the one object the detectors are built from.
#pragma once

#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "watch/analysis.h"
#include "watch/ast.h"
#include "watch/diagnostic.h"
#include "watch/program.h"
#include "watch/source.h"

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

// Parses, checks and compiles. Never throws on bad input: errors come back as diagnostics.
std::variant<Watchpoint, CompileError> compile_watchpoint(std::string name, SourceText source);

}  // namespace dw::watch
