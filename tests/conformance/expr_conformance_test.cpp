// Every expression and window case of the independent reference (tests/conformance_expr/ and
// tests/conformance_window/, copied from shared/, docs/design.md §4b: arithmetic, neighbour
// aggregates; §4c: windows in time), every reading it has
// expected matches for, every combination of the optimizations: the same set of (t, slots).
//   centralized (ordered)        expected.centralized.jsonl
//   distributed, consistent      expected.distributed.jsonl
//   centralized, any             expected.any.jsonl            (*_static cases)
//   distributed, simultaneous    the centralized set of its shape, ordered and any (*_static)
#include "conformance_case.h"

namespace dw {
namespace {

using namespace dw::testing;

struct Param {
  fs::path dir;
  std::string reading;  // centralized, distributed, any, simultaneous-ordered, simultaneous-any
};

void PrintTo(const Param& p, std::ostream* os) { *os << p.dir.filename().string() << " " << p.reading; }

class ExpressionConformance : public ::testing::TestWithParam<Param> {};

TEST_P(ExpressionConformance, MatchesTheReferenceUnderEveryOptimizationCombination) {
  const Param& p = GetParam();
  const LoadedCase c = load_case(p.dir);
  const bool any = p.reading.ends_with("any");
  const std::string expected = any ? "any" : p.reading == "distributed" ? "distributed" : "centralized";
  const std::set<CaseMatch> want = expected_matches(p.dir / ("expected." + expected + ".jsonl"));
  ASSERT_FALSE(want.empty());
  for (int bits = 0; bits < 8; ++bits) {
    watch::DetectorOptions o{optimizations_from_bits(bits), 0};
    watch::Algorithm algorithm = watch::Algorithm::Centralized;
    if (any) o.shape = watch::GroupShape::Any;
    if (p.reading == "distributed" || p.reading.starts_with("simultaneous")) algorithm = watch::Algorithm::Distributed;
    if (p.reading.starts_with("simultaneous")) {
      o.states = watch::States::Simultaneous;
      if (!any) o.shape = watch::GroupShape::Ordered;
    }
    const std::set<CaseMatch> got = replay_case(c, algorithm, o);
    EXPECT_EQ(got.size(), want.size()) << "optimizations " << bits;
    EXPECT_TRUE(got == want) << "optimizations " << bits;
  }
}

std::vector<Param> params() {
  std::vector<Param> out;
  std::vector<fs::path> cases = case_dirs(DWATCH_CONFORMANCE_EXPR_DIR);
  for (const fs::path& c : case_dirs(DWATCH_CONFORMANCE_WINDOW_DIR)) cases.push_back(c);
  for (const fs::path& c : cases) {
    out.push_back({c, "centralized"});
    out.push_back({c, "distributed"});
    if (!c.filename().string().ends_with("_static")) continue;
    for (const char* r : {"any", "simultaneous-ordered", "simultaneous-any"}) out.push_back({c, r});
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(Reference, ExpressionConformance, ::testing::ValuesIn(params()), [](const auto& info) {
  std::string name = info.param.dir.filename().string() + "_" + info.param.reading;
  std::replace(name.begin(), name.end(), '-', '_');
  return name;
});

TEST(ExpressionConformanceSuite, HasTheCases) { EXPECT_GE(case_dirs(DWATCH_CONFORMANCE_EXPR_DIR).size(), 3u); }
TEST(WindowConformanceSuite, HasTheCases) { EXPECT_GE(case_dirs(DWATCH_CONFORMANCE_WINDOW_DIR).size(), 1u); }

}  // namespace
}  // namespace dw
