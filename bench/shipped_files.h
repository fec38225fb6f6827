// The files dwatch ships beside the program, which the benches read: the scenarios (with their
// Lua library, scenarios/lua/) and the script that draws the paper's plots. An installed dwatch
// finds them under its own prefix, PREFIX/share/dwatch/ (cmake --install puts them there:
// bench/CMakeLists.txt), from where the running program is (/proc/self/exe: PREFIX/bin/dwatch),
// so that a checkout moved or gone changes nothing. A program in the build tree (dwatch, the
// tests) reads the source tree it was built from.
#pragma once

#include <string>

namespace dw::bench {

struct ShippedFiles {
  std::string scenarios;    // the scenario files: scenarios/, or share/dwatch/scenarios
  std::string lua;          // the Lua library and its scenarios: the scenarios' lua/
  std::string plot_script;  // scripts/plot_paper.py, or share/dwatch/plot_paper.py
};

// Where this program finds them.
ShippedFiles shipped_files();

}  // namespace dw::bench
