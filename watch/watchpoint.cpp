#include "watch/watchpoint.h"

#include "watch/parser.h"
#include "watch/windows.h"

namespace dw::watch {

std::string name_problem(std::string_view name) {
  if (name.empty()) return "a watchpoint's name cannot be empty";
  for (const char c : name)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      return "a watchpoint's name holds no control character (byte " + std::to_string(static_cast<unsigned char>(c)) +
             ")";
  if (name.front() == '"') return "a watchpoint's name does not start with a double quote";
  const std::string_view digits = name.substr(name.front() == '-' || name.front() == '+' ? 1 : 0);
  if (!digits.empty() && digits.find_first_not_of("0123456789") == std::string_view::npos)
    return "a watchpoint's name is not an integer ('matches " + std::string(name) + "' would be a step): add a letter";
  return {};
}

std::variant<Watchpoint, CompileError> compile_watchpoint(std::string name, SourceText source, WindowKeeping keeping) {
  auto shared = std::make_shared<const SourceText>(std::move(source));
  ParseResult parsed = parse(*shared);
  if (!parsed.ok()) return CompileError{shared, std::move(parsed.diagnostics)};
  if (std::vector<Diagnostic> too_large = write_out_windows(parsed.ast, keeping); !too_large.empty())
    return CompileError{shared, std::move(too_large)};
  Analysis analysis = analyze(parsed.ast);
  Program program(parsed.ast, analysis);
  return Watchpoint{std::move(name), shared, std::move(parsed.ast), std::move(analysis), std::move(program)};
}

}  // namespace dw::watch
