// Every group-shape case of the independent reference (tests/conformance_shapes/, copied from
// shared/conformance_shapes/, docs/design.md §4a), every shape, every combination of the optimizations:
// the centralized detector finds exactly the expected matches; the distributed one in
// simultaneous-state mode finds exactly them on a fixed topology and a subset, never a match
// outside them, on a moving one.
#include "conformance_case.h"

namespace dw {
namespace {

using namespace dw::testing;

struct Param {
  fs::path dir;
  watch::GroupShape shape;
  watch::Algorithm algorithm;
};

void PrintTo(const Param& p, std::ostream* os) {
  *os << p.dir.filename().string() << " " << watch::shape_name(p.shape) << " " << watch::algorithm_name(p.algorithm);
}

class ShapeConformance : public ::testing::TestWithParam<Param> {};

TEST_P(ShapeConformance, MatchesTheReferenceUnderEveryOptimizationCombination) {
  const Param& p = GetParam();
  const LoadedCase c = load_case(p.dir);
  const std::set<CaseMatch> want =
      expected_matches(p.dir / ("expected." + std::string(shape_name(p.shape)) + ".jsonl"));
  ASSERT_FALSE(want.empty());
  const bool fixed_topology = p.dir.filename().string().ends_with("_static");
  for (int bits = 0; bits < 8; ++bits) {
    watch::DetectorOptions o{optimizations_from_bits(bits), 0};
    o.shape = p.shape;
    if (p.algorithm == watch::Algorithm::Distributed) o.states = watch::States::Simultaneous;
    watch::DetectorStats stats;
    const std::set<CaseMatch> got = replay_case(c, p.algorithm, o, &stats);
    if (p.algorithm == watch::Algorithm::Centralized || fixed_topology) {
      EXPECT_EQ(got.size(), want.size()) << "optimizations " << bits;
      EXPECT_TRUE(got == want) << "optimizations " << bits;
      if (p.algorithm == watch::Algorithm::Distributed) {
        EXPECT_EQ(stats.lost, 0u);
      }
    } else {
      for (const CaseMatch& m : got) EXPECT_TRUE(want.count(m)) << "a match outside the reference at t " << m.first;
      // What is missing was lost to the moving topology, and counted.
      if (got.size() < want.size()) {
        EXPECT_GT(stats.lost, 0u) << "optimizations " << bits;
      }
      EXPECT_FALSE(got.empty());
    }
  }
}

std::vector<Param> params() {
  std::vector<Param> out;
  for (const fs::path& c : case_dirs(DWATCH_CONFORMANCE_SHAPES_DIR))
    for (auto s : {watch::GroupShape::Chain, watch::GroupShape::Ordered, watch::GroupShape::Any})
      for (auto a : {watch::Algorithm::Centralized, watch::Algorithm::Distributed}) out.push_back({c, s, a});
  return out;
}

INSTANTIATE_TEST_SUITE_P(Reference, ShapeConformance, ::testing::ValuesIn(params()), [](const auto& info) {
  return info.param.dir.filename().string() + "_" + watch::shape_name(info.param.shape) + "_" +
         watch::algorithm_name(info.param.algorithm);
});

TEST(ShapeConformanceSuite, HasEveryCase) { EXPECT_EQ(case_dirs(DWATCH_CONFORMANCE_SHAPES_DIR).size(), 3u); }

}  // namespace
}  // namespace dw
