// Every case of the independent reference (tests/conformance/, copied from shared/conformance/),
// both algorithms, every combination of the optimizations: the same set of (t, slots).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "sim/trace.h"
#include "watch/make_detector.h"
#include "watch/watchpoint.h"

namespace dw {
namespace {

namespace fs = std::filesystem;
using Match = std::pair<int64_t, std::vector<std::pair<std::string, uint32_t>>>;

std::vector<fs::path> cases() {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(DWATCH_CONFORMANCE_DIR))
    if (e.is_directory()) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::set<Match> expected(const fs::path& file) {
  std::set<Match> out;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) {
    if (line.empty()) continue;
    // nlohmann's ordered_json keeps the slots in the file's order, which is slot order.
    const auto j = nlohmann::ordered_json::parse(line);
    Match m{j["t"].get<int64_t>(), {}};
    for (const auto& [slot, id] : j["slots"].items()) m.second.emplace_back(slot, id.get<uint32_t>());
    out.insert(std::move(m));
  }
  return out;
}

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
  auto trace = sim::read_trace((p.dir / "trace.jsonl").string());
  ASSERT_TRUE(std::holds_alternative<sim::Trace>(trace));
  const sim::Trace& tr = std::get<sim::Trace>(trace);
  auto compiled = watch::compile_watchpoint(
      p.dir.filename().string(), watch::SourceText((p.dir / "watch.txt").string(), slurp(p.dir / "watch.txt")));
  ASSERT_TRUE(std::holds_alternative<watch::Watchpoint>(compiled));
  const watch::Watchpoint& w = std::get<watch::Watchpoint>(compiled);
  const std::set<Match> want =
      expected(p.dir / ("expected." + std::string(watch::algorithm_name(p.algorithm)) + ".jsonl"));
  ASSERT_FALSE(want.empty());

  // Frames over what the watchpoint reads, as `dwatch replay` makes them.
  auto reader =
      std::get<sim::FrameReader>(sim::FrameReader::make(tr, w.program.variables, sim::default_frame_budget()));
  for (int bits = 0; bits < 8; ++bits) {
    watch::DetectorOptions o;
    o.optimizations = {(bits & 1) != 0, (bits & 2) != 0, (bits & 4) != 0};
    std::set<Match> got;
    auto d = watch::make_detector(p.algorithm, w, reader.universe(), o,
                                  [&](int64_t t, std::span<const watch::ModuleId> ids) {
                                    const size_t k = w.program.slot_names.size();
                                    for (size_t i = 0; i < ids.size(); i += k) {
                                      Match m{t, {}};
                                      for (size_t s = 0; s < k; ++s)
                                        m.second.emplace_back(w.program.slot_names[s], ids[i + s]);
                                      got.insert(std::move(m));
                                    }
                                  });
    for (int64_t s = 0; s < tr.step_count(); ++s) d->observe(reader.frame(s));
    EXPECT_EQ(got.size(), want.size()) << "optimizations " << bits;
    EXPECT_TRUE(got == want) << "optimizations " << bits;
  }
}

std::vector<Param> params() {
  std::vector<Param> out;
  for (const fs::path& c : cases())
    for (auto a : {watch::Algorithm::Centralized, watch::Algorithm::Distributed}) out.push_back({c, a});
  return out;
}

INSTANTIATE_TEST_SUITE_P(Reference, Conformance, ::testing::ValuesIn(params()), [](const auto& info) {
  return info.param.dir.filename().string() + "_" + watch::algorithm_name(info.param.algorithm);
});

TEST(ConformanceSuite, HasEveryCase) { EXPECT_EQ(cases().size(), 12u); }

}  // namespace
}  // namespace dw
