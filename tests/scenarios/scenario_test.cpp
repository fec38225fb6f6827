// Runs every scenario case file in tests/scenarios/cases/: a scenario with its expected
// diagnostics as comments,
//   # expect: ok
//   # expect: LINE:COL: MESSAGE-FRAGMENT      (one line per diagnostic, in file order)
// and checks the loader reports exactly those, each as `file:line:col: error:` with a caret.
#include "scenarios/scenario.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "sim/session.h"
#include "tests/case_file.h"

namespace dw::scenarios {
namespace {

using test_support::ExpectedDiagnostic;

std::vector<std::filesystem::path> case_files() { return test_support::case_files(DWATCH_SCENARIO_CASES_DIR, ".toml"); }

class ScenarioCase : public ::testing::TestWithParam<std::filesystem::path> {};

TEST_P(ScenarioCase, GivesExactlyTheExpectedDiagnostics) {
  const std::string path = GetParam().string();
  const test_support::CaseFile c = test_support::read_case_file(path);
  ASSERT_TRUE(c.malformed.empty()) << "bad expectation: " << c.malformed.front();
  const bool ok = c.ok;
  std::vector<ExpectedDiagnostic> expected = c.expected;
  ASSERT_TRUE(ok != !expected.empty()) << "a case says either 'ok' or what it expects";
  std::sort(expected.begin(), expected.end(), [](const ExpectedDiagnostic& a, const ExpectedDiagnostic& b) {
    return std::tie(a.line, a.column) < std::tie(b.line, b.column);
  });

  auto loaded = load_scenario(path);
  if (ok) {
    ASSERT_TRUE(std::holds_alternative<Scenario>(loaded)) << std::get<std::string>(loaded);
    // It runs, too.
    Scenario& s = std::get<Scenario>(loaded);
    sim::Session run(*s.model, *s.world, {.threads = s.threads});
    run.run_until(s.steps);
    EXPECT_EQ(run.current() + 1, s.steps);
    return;
  }
  ASSERT_TRUE(std::holds_alternative<std::string>(loaded)) << "the scenario loaded, but should not have";
  const std::string rendered = std::get<std::string>(loaded);
  std::vector<ExpectedDiagnostic> got;
  std::istringstream out(rendered);
  std::string previous;
  for (std::string line; std::getline(out, line); previous = line) {
    // A header line: PATH:LINE:COL: error: MESSAGE
    if (line.rfind(path + ":", 0) == 0) {
      auto e = test_support::parse_location(line.substr(path.size() + 1));
      if (e && e->fragment.rfind("error: ", 0) == 0) {
        e->fragment.erase(0, 7);
        got.push_back(*e);
      }
    }
    if (line.find('^') != std::string::npos) {
      EXPECT_FALSE(previous.empty()) << "a caret under a source line";
    }
  }
  ASSERT_EQ(got.size(), expected.size()) << rendered;
  for (size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].line, expected[i].line) << rendered;
    EXPECT_EQ(got[i].column, expected[i].column) << rendered;
    EXPECT_NE(got[i].fragment.find(expected[i].fragment), std::string::npos)
        << "message: " << got[i].fragment << "\nexpected fragment: " << expected[i].fragment;
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, ScenarioCase, ::testing::ValuesIn(case_files()),
                         [](const auto& info) { return info.param.stem().string(); });

TEST(ScenarioCases, ThereAreCasesToRun) { EXPECT_GE(case_files().size(), 20u); }

TEST(Scenario, AMissingFileIsAnError) {
  auto loaded = load_scenario("/nonexistent/x.toml");
  ASSERT_TRUE(std::holds_alternative<std::string>(loaded));
  EXPECT_NE(std::get<std::string>(loaded).find("cannot read"), std::string::npos);
}

// A dotted key nests a table per part, by recursion in toml++: 40,000 parts crashed it. Past 256
// parts, as a key, a table header or an array of tables, it is an error at the dot; dots in
// floats, strings and comments are no key's.
TEST(Scenario, ADottedKeyTooDeepIsAnErrorNotACrash) {
  std::string parts;
  for (int i = 0; i < 40'000; ++i) parts += "a.";
  const std::string line = "[lattice]\nkind = \"ring\"\nsize = [4]\n[[program]]\nname = \"token_ring\"\n";
  for (const std::string& bad :
       {parts + "a = 1\n", "[" + parts + "a]\n", "[[" + parts + "a]]\n", "x = { " + parts + "a = 1 }\n"}) {
    auto loaded = load_scenario_text("deep.toml", line + bad);
    ASSERT_TRUE(std::holds_alternative<std::string>(loaded)) << bad.substr(0, 10);
    EXPECT_NE(std::get<std::string>(loaded).find("deep.toml:6:"), std::string::npos) << std::get<std::string>(loaded);
    EXPECT_NE(std::get<std::string>(loaded).find("a dotted key of more than 256 parts"), std::string::npos);
  }
  std::string floats = "[view]\ncamera_eye = [1.5, 2.5, 3.5]\n# " + parts + "\ndescription = \"" + parts + "\"\n";
  std::string many = "x = [";
  for (int i = 0; i < 400; ++i) many += "1.5, ";
  auto loaded = load_scenario_text("ok.toml", line + "[extra]\n" + many + "2.5]\n" + floats);
  ASSERT_TRUE(std::holds_alternative<std::string>(loaded));  // [extra] is an unknown table
  EXPECT_EQ(std::get<std::string>(loaded).find("dotted key"), std::string::npos) << std::get<std::string>(loaded);
}

// Every mistake is found, the first 20 shown: 100,000 bad events took minutes to place and made
// 20 MB of messages.
TEST(Scenario, TheFirstTwentyMistakesAreShownAndTheRestCounted) {
  std::string text = "steps = 5\n[lattice]\nkind = \"ring\"\nsize = [4]\n[[program]]\nname = \"token_ring\"\n";
  for (int i = 0; i < 30'000; ++i) text += "[[event]]\nat = 1\nmodule = 99\nremove = true\n";
  auto loaded = load_scenario_text("bad.toml", text);
  ASSERT_TRUE(std::holds_alternative<std::string>(loaded));
  const std::string& errors = std::get<std::string>(loaded);
  EXPECT_EQ(std::count(errors.begin(), errors.end(), '^'), 20);
  EXPECT_NE(errors.find("bad.toml:9:"), std::string::npos) << errors.substr(0, 300);
  EXPECT_NE(errors.find("bad.toml: 29980 more errors not shown (the first 20 are above)"), std::string::npos)
      << errors.substr(errors.size() - 300);
}

// Each watchpoint keeps a detector, a history and statistics: 100,000 of them in a 5 MB file took
// 2.5 GB and minutes. A scenario holds watch::kMaxWatchpoints at most.
TEST(Scenario, ItHoldsAtMostAThousandWatchpoints) {
  const std::string head = "steps = 2\n[lattice]\nkind = \"ring\"\nsize = [4]\n[[program]]\nname = \"token_ring\"\n";
  auto with = [&](size_t n) {
    std::string text = head;
    for (size_t i = 0; i < n; ++i)
      text += "[[watch]]\nname = \"w" + std::to_string(i) + "\"\ntext = \"modules(a); a.token = 1\"\n";
    return load_scenario_text("many.toml", text);
  };
  EXPECT_TRUE(std::holds_alternative<Scenario>(with(watch::kMaxWatchpoints)));
  const auto over = with(watch::kMaxWatchpoints + 1);
  ASSERT_TRUE(std::holds_alternative<std::string>(over));
  EXPECT_NE(
      std::get<std::string>(over).find("many.toml:7:1: error: a scenario holds at most 1000 watchpoints, not 1001"),
      std::string::npos)
      << std::get<std::string>(over).substr(0, 300);
}

// A bound is the number as a scenario writes it: 0.015 is the largest contact threshold, and was
// refused as "between 0 and 0.015, not 0.015" (it was checked against the float nearest 0.015,
// just below it).
TEST(Scenario, ABoundItselfIsWithinTheBound) {
  const std::string head =
      "[lattice]\nkind = \"cubic\"\nsize = [2, 2, 2]\n[[program]]\nname = \"token_ring\"\n[physics]\n";
  const auto at = load_scenario_text("at.toml", head + "contact_threshold = 0.015\n");
  ASSERT_TRUE(std::holds_alternative<Scenario>(at)) << std::get<std::string>(at);
  const auto over = load_scenario_text("over.toml", head + "contact_threshold = 0.0150001\n");
  ASSERT_TRUE(std::holds_alternative<std::string>(over));
  EXPECT_NE(std::get<std::string>(over).find("must be between 0 and 0.015, not 0.0150001"), std::string::npos)
      << std::get<std::string>(over);
}

// More substeps for a fast island (physics/settings.h) are at least the substeps of every step:
// a ceiling below the floor is refused at its key.
TEST(Scenario, MaxSubstepsBelowSubstepsIsRefusedAtItsKey) {
  const std::string head =
      "[lattice]\nkind = \"cubic\"\nsize = [2, 2, 2]\n[[program]]\nname = \"token_ring\"\n[physics]\n";
  const auto below = load_scenario_text("below.toml", head + "substeps = 8\nmax_substeps = 4\n");
  ASSERT_TRUE(std::holds_alternative<std::string>(below));
  EXPECT_NE(std::get<std::string>(below).find("below.toml:8:16: error:"), std::string::npos)
      << std::get<std::string>(below);
  EXPECT_NE(std::get<std::string>(below).find("is below substeps (8)"), std::string::npos)
      << std::get<std::string>(below);
  // Unset, the ceiling rises to the substeps asked for.
  const auto raised = load_scenario_text("raised.toml", head + "substeps = 32\n");
  ASSERT_TRUE(std::holds_alternative<Scenario>(raised)) << std::get<std::string>(raised);
}

TEST(Scenario, OverridesWinOverTheFile) {
  auto loaded = load_scenario_text("x.toml", R"toml(seed = 3
[lattice]
kind = "line"
size = [3]
[[program]]
name = "random_vars"
tuple = [2]
[[watch]]
name = "w"
text = "modules(a); (a.x1 = 1)"
algorithm = "distributed"
)toml",
                                   {uint64_t{9}, watch::Algorithm::Centralized});
  ASSERT_TRUE(std::holds_alternative<Scenario>(loaded)) << std::get<std::string>(loaded);
  const Scenario& s = std::get<Scenario>(loaded);
  EXPECT_EQ(s.model->seed, 9u);
  EXPECT_EQ(s.model->watches[0].algorithm, watch::Algorithm::Centralized);
  EXPECT_EQ(s.name, "x");
  EXPECT_EQ(s.steps, 100);
}

// A watchpoint written in the scenario keeps its own text only, while its diagnostics point into
// the scenario file: 3,000 of them in a 300 KB file once kept 3,000 copies of the file (0.9 GB). (999 here, with the
// one more below as many as a scenario may hold.)
TEST(Scenario, AWatchpointKeepsItsOwnTextAndPointsIntoTheFile) {
  std::string text = "[lattice]\nkind = \"line\"\nsize = [3]\n[[program]]\nname = \"random_vars\"\ntuple = [2]\n";
  for (int w = 0; w < 999; ++w)
    text +=
        "[[watch]]\nname = \"w" + std::to_string(w) + "\"\ntext = \"modules(a); a.x1 = " + std::to_string(w) + "\"\n";
  auto loaded = load_scenario_text("x.toml", text);
  ASSERT_TRUE(std::holds_alternative<Scenario>(loaded)) << std::get<std::string>(loaded);
  const Scenario& s = std::get<Scenario>(loaded);
  ASSERT_EQ(s.model->watches.size(), 999u);
  EXPECT_EQ(s.model->watches[998].watchpoint.source->text(), "modules(a); a.x1 = 998");
  // A mistake in the last one is reported at its line and column in the file.
  text += "[[watch]]\nname = \"bad\"\ntext = \"modules(a); a.nosuch = 1\"\n";
  const auto bad = load_scenario_text("x.toml", text);
  ASSERT_TRUE(std::holds_alternative<std::string>(bad));
  const std::string line = std::to_string(6 + 3 * 999 + 3);  // six lines, three a watchpoint
  EXPECT_NE(std::get<std::string>(bad).find("x.toml:" + line + ":21: error: watchpoint \"bad\" reads 'nosuch'"),
            std::string::npos)
      << std::get<std::string>(bad);
}

// Every scenario shipped in scenarios/ loads.
TEST(Scenario, ShippedScenariosLoad) {
  int count = 0;
  for (const auto& e : std::filesystem::directory_iterator(DWATCH_SCENARIOS_DIR)) {
    if (e.path().extension() != ".toml") continue;
    ++count;
    auto loaded = load_scenario(e.path().string());
    EXPECT_TRUE(std::holds_alternative<Scenario>(loaded)) << std::get<std::string>(loaded);
  }
  EXPECT_GE(count, 5);
}

}  // namespace
}  // namespace dw::scenarios
