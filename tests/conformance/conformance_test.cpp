// Every case of the independent reference (tests/conformance/, copied from shared/conformance/),
// both algorithms, every combination of the optimizations: the same set of (t, slots).
#include "conformance_case.h"

namespace dw {
namespace {

using namespace dw::testing;

struct Param {
  fs::path dir;
  watch::Algorithm algorithm;
};

void PrintTo(const Param& p, std::ostream* os) {
  *os << p.dir.filename().string() << " " << watch::algorithm_name(p.algorithm);
}

class Conformance : public ::testing::TestWithParam<Param> {};

TEST_P(Conformance, MatchesTheReferenceUnderEveryOptimizationCombination) {
  const Param& p = GetParam();
  const LoadedCase c = load_case(p.dir);
  const std::set<CaseMatch> want =
      expected_matches(p.dir / ("expected." + std::string(watch::algorithm_name(p.algorithm)) + ".jsonl"));
  ASSERT_FALSE(want.empty());
  for (int bits = 0; bits < 8; ++bits) {
    const std::set<CaseMatch> got = replay_case(c, p.algorithm, {optimizations_from_bits(bits), 0});
    EXPECT_EQ(got.size(), want.size()) << "optimizations " << bits;
    EXPECT_TRUE(got == want) << "optimizations " << bits;
  }
}

std::vector<Param> params() {
  std::vector<Param> out;
  for (const fs::path& c : case_dirs(DWATCH_CONFORMANCE_DIR))
    for (auto a : {watch::Algorithm::Centralized, watch::Algorithm::Distributed}) out.push_back({c, a});
  return out;
}

INSTANTIATE_TEST_SUITE_P(Reference, Conformance, ::testing::ValuesIn(params()), [](const auto& info) {
  return info.param.dir.filename().string() + "_" + watch::algorithm_name(info.param.algorithm);
});

TEST(ConformanceSuite, HasEveryCase) { EXPECT_EQ(case_dirs(DWATCH_CONFORMANCE_DIR).size(), 12u); }

}  // namespace
}  // namespace dw
