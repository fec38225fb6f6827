// Case files for the diagnostics suites (watchpoints, scenarios): a file followed by its expected
// diagnostics as comments, which both languages ignore:
//   # expect: ok
//   # expect: LINE:COL: MESSAGE-FRAGMENT      (one line per diagnostic, in order)
#pragma once

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace dw::test_support {

struct ExpectedDiagnostic {
  uint32_t line = 0, column = 0;
  std::string fragment;  // the text after "LINE:COL:", leading spaces dropped
};

// "LINE:COL: rest" -> its parts; nothing when it does not start with a location.
inline std::optional<ExpectedDiagnostic> parse_location(const std::string& text) {
  ExpectedDiagnostic e;
  char c1 = 0, c2 = 0;
  std::istringstream fields(text);
  fields >> e.line >> c1 >> e.column >> c2;
  if (!fields || c1 != ':' || c2 != ':') return std::nullopt;
  std::getline(fields, e.fragment);
  e.fragment.erase(0, e.fragment.find_first_not_of(' '));
  return e;
}

struct CaseFile {
  std::string text;
  bool ok = false;                           // "# expect: ok"
  std::vector<ExpectedDiagnostic> expected;  // in file order
  std::vector<std::string> malformed;        // expectation lines that could not be read
};

inline CaseFile read_case_file(const std::filesystem::path& path) {
  CaseFile c;
  std::ifstream in(path);
  std::stringstream buffer;
  buffer << in.rdbuf();
  c.text = buffer.str();
  std::istringstream lines(c.text);
  const std::string tag = "# expect: ";
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind(tag, 0) != 0) continue;
    const std::string rest = line.substr(tag.size());
    if (rest == "ok") c.ok = true;
    else if (auto e = parse_location(rest)) c.expected.push_back(*e);
    else c.malformed.push_back(line);
  }
  return c;
}

// The files in `dir` ending in `extension`, sorted.
inline std::vector<std::filesystem::path> case_files(const std::filesystem::path& dir, const std::string& extension) {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == extension) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace dw::test_support
