#include "app/output_files.h"

#include <iostream>

namespace dw::app {

bool open_output(const std::string& path, const char* what, std::ofstream& file, std::ostream*& out) {
  if (path.empty()) return true;
  if (path == "-") {
    out = &std::cout;
    return true;
  }
  file.open(path, std::ios::binary);
  if (!file) {
    std::cerr << path << ": error: cannot write the " << what << " file\n";
    return false;
  }
  out = &file;
  return true;
}

bool flush_outputs(const std::vector<std::pair<std::ostream*, const std::string*>>& outputs) {
  for (const auto& [stream, path] : outputs) {
    if (stream != nullptr && !stream->flush()) {
      std::cerr << *path << ": error: writing failed\n";
      return false;
    }
  }
  return true;
}

}  // namespace dw::app
