// Reading an input file whole, with the reason when it cannot be read ("Is a directory" included:
// on Linux a folder opens as a file and reads as empty, which would be reported as a parse error).
#pragma once

#include <optional>
#include <string>

namespace dw::sim {

// The file's bytes, or nothing with `error` set to "cannot read PATH: REASON".
std::optional<std::string> read_file(const std::string& path, std::string* error);
// Empty when `path` names a readable file that is not a directory, else "cannot read PATH: REASON".
std::string check_readable(const std::string& path);

}  // namespace dw::sim
