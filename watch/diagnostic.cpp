#include "watch/diagnostic.h"

#include <algorithm>

namespace dw::watch {

std::string format_diagnostic(const SourceText& source, const Diagnostic& d) {
  const Location loc = source.locate(d.span.begin);
  std::string out = source.name() + ":" + std::to_string(loc.line) + ":" + std::to_string(loc.column) +
                    ": error: " + d.message + "\n";
  const std::string_view line = source.line_at(d.span.begin);
  out.append(line);
  out += '\n';
  // Copy tabs from the source line so that the caret lines up in any tab width.
  const uint32_t col0 = loc.column - 1;
  for (uint32_t i = 0; i < col0 && i < line.size(); ++i) out += line[i] == '\t' ? '\t' : ' ';
  out += '^';
  const uint32_t visible = static_cast<uint32_t>(line.size()) > col0 ? static_cast<uint32_t>(line.size()) - col0 : 0;
  const uint32_t tildes = std::min(d.span.length(), visible);
  for (uint32_t i = 1; i < tildes; ++i) out += '~';
  out += '\n';
  return out;
}

std::string format_diagnostics(const SourceText& source, const std::vector<Diagnostic>& ds) {
  std::string out;
  for (const Diagnostic& d : ds) out += format_diagnostic(source, d);
  return out;
}

}  // namespace dw::watch
