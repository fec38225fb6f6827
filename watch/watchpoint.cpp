#include "watch/watchpoint.h"

#include "watch/parser.h"

namespace dw::watch {

std::variant<Watchpoint, CompileError> compile_watchpoint(std::string name, SourceText source) {
  auto shared = std::make_shared<const SourceText>(std::move(source));
  ParseResult parsed = parse(*shared);
  if (!parsed.ok()) return CompileError{shared, std::move(parsed.diagnostics)};
  Analysis analysis = analyze(parsed.ast);
  Program program(parsed.ast, analysis);
  return Watchpoint{std::move(name), shared, std::move(parsed.ast), std::move(analysis), std::move(program)};
}

}  // namespace dw::watch
