// Runs every language case file in tests/watch/cases/. A case is a watchpoint followed by its
// expected diagnostics as comments (which the language ignores):
//   # expect: ok
//   # expect: LINE:COL: MESSAGE-FRAGMENT      (one line per diagnostic, in order)
#include <gtest/gtest.h>

#include "tests/case_file.h"
#include "watch/parser.h"

namespace dw::watch {
namespace {

std::vector<std::filesystem::path> case_files() { return test_support::case_files(DWATCH_CASES_DIR, ".watch"); }

class LanguageCase : public ::testing::TestWithParam<std::filesystem::path> {};

TEST_P(LanguageCase, GivesExactlyTheExpectedDiagnostics) {
  const test_support::CaseFile c = test_support::read_case_file(GetParam());
  ASSERT_TRUE(c.malformed.empty()) << "bad expectation: " << c.malformed.front();
  const std::string& text = c.text;
  const auto& expected = c.expected;
  ASSERT_TRUE(c.ok != !expected.empty()) << "a case says either 'ok' or what it expects";

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
