// Runs every language case file in tests/watch/cases/. A case is a watchpoint followed by its
// expected diagnostics as comments (which the language ignores):
//   # expect: ok
//   # expect: LINE:COL: MESSAGE-FRAGMENT      (one line per diagnostic, in order)
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "watch/parser.h"

namespace dw::watch {
namespace {

struct Expected {
  uint32_t line, column;
  std::string fragment;
};

std::vector<std::filesystem::path> case_files() {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(DWATCH_CASES_DIR))
    if (e.path().extension() == ".watch") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

class LanguageCase : public ::testing::TestWithParam<std::filesystem::path> {};

TEST_P(LanguageCase, GivesExactlyTheExpectedDiagnostics) {
  std::ifstream in(GetParam());
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();

  std::vector<Expected> expected;
  bool ok = false;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    const std::string tag = "# expect: ";
    if (line.rfind(tag, 0) != 0) continue;
    const std::string rest = line.substr(tag.size());
    if (rest == "ok") {
      ok = true;
      continue;
    }
    Expected e{};
    char colon1, colon2;
    std::istringstream fields(rest);
    fields >> e.line >> colon1 >> e.column >> colon2;
    ASSERT_TRUE(fields && colon1 == ':' && colon2 == ':') << "bad expectation: " << line;
    std::getline(fields, e.fragment);
    e.fragment.erase(0, e.fragment.find_first_not_of(' '));
    expected.push_back(e);
  }
  ASSERT_TRUE(ok != !expected.empty()) << "a case says either 'ok' or what it expects";

  SourceText source(GetParam().filename().string(), text);
  const ParseResult r = parse(source);
  const std::string rendered = format_diagnostics(source, r.diagnostics);
  ASSERT_EQ(r.diagnostics.size(), expected.size()) << rendered;
  for (size_t i = 0; i < expected.size(); ++i) {
    const Location loc = source.locate(r.diagnostics[i].span.begin);
    EXPECT_EQ(loc.line, expected[i].line) << rendered;
    EXPECT_EQ(loc.column, expected[i].column) << rendered;
    EXPECT_NE(r.diagnostics[i].message.find(expected[i].fragment), std::string::npos)
        << "message: " << r.diagnostics[i].message << "\nexpected fragment: " << expected[i].fragment;
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, LanguageCase, ::testing::ValuesIn(case_files()),
                         [](const auto& info) { return info.param.stem().string(); });

TEST(LanguageCases, ThereAreCasesToRun) { EXPECT_GE(case_files().size(), 20u); }

}  // namespace
}  // namespace dw::watch
