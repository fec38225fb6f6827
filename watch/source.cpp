#include "watch/source.h"

#include <algorithm>

namespace dw::watch {

Location SourceText::locate(uint32_t offset) const {
  offset = std::min<uint32_t>(offset - std::min(offset, base_), static_cast<uint32_t>(text_.size()));
  Location loc;
  for (uint32_t i = 0; i < offset; ++i) {
    if (text_[i] == '\n') {
      ++loc.line;
      loc.column = 1;
    } else {
      ++loc.column;
    }
  }
  return loc;
}

std::string_view SourceText::line_at(uint32_t offset) const {
  offset = std::min<uint32_t>(offset - std::min(offset, base_), static_cast<uint32_t>(text_.size()));
  size_t begin = 0;
  if (offset > 0) {
    const size_t nl = text_.rfind('\n', offset - 1);
    if (nl != std::string::npos) begin = nl + 1;
  }
  size_t end = text_.find('\n', begin);
  if (end == std::string::npos) end = text_.size();
  std::string_view line = std::string_view(text_).substr(begin, end - begin);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return line;
}

}  // namespace dw::watch
