// Output files named on the command line: opened before a run, so that a bad path costs nothing
// and is bad input; flushed and checked after it, so that a failed write is a runtime failure.
#pragma once

#include <fstream>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace dw::app {

// Opens `path` (nothing to do when empty; "-" is stdout) and points `out` at it. False, with
// `path: error: cannot write the WHAT file` on stderr, when it cannot be written.
bool open_output(const std::string& path, const char* what, std::ofstream& file, std::ostream*& out);

// Flushes every (stream, path) given a stream; false, naming the path, when one write failed.
bool flush_outputs(const std::vector<std::pair<std::ostream*, const std::string*>>& outputs);

}  // namespace dw::app
