// Retroactive watchpoints over every shipped scenario (docs/design.md §7): each scenario's watchpoints,
// with either algorithm, taken out before step 0 and added back partway through a session, find
// exactly what a run that had them from step 0 finds, and the session's states hash the same.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "scenarios/scenario.h"
#include "sim/session.h"
#include "sim/state.h"
#include "tests/sim/run_trail.h"

namespace dw::scenarios {
namespace {

namespace fs = std::filesystem;

// The cells of a scenario file's lattice, read from its `size = [...]` line (every gtest run of
// this binary lists the tests: loading each scenario for it would build a million-module model).
uint64_t lattice_cells(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("size = [", 0) == 0) {
      uint64_t cells = 1;
      std::istringstream sizes(line.substr(8));
      for (uint64_t n; sizes >> n; sizes.ignore(1)) cells *= n;
      return cells;
    }
  return 0;
}

// The shipped scenarios of at most 100,000 modules: a million stepped 50 steps twice takes minutes
// (many more under the sanitizers); reconfigure_large.toml runs smaller in physics_scenarios_test.cpp.
std::vector<fs::path> shipped() {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(DWATCH_SCENARIOS_DIR))
    if (e.path().extension() == ".toml" && lattice_cells(e.path()) <= 100'000) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

Scenario load(const fs::path& path, watch::Algorithm algorithm) {
  ScenarioOverrides overrides;
  overrides.algorithm = algorithm;
  auto loaded = load_scenario(path.string(), overrides);
  if (auto* e = std::get_if<std::string>(&loaded)) ADD_FAILURE() << *e;
  return std::move(std::get<Scenario>(loaded));
}

// Runs to `steps` through any pauses.
void run_through(sim::Session& session, int64_t steps, const sim::Session::StepObserver& observer = {}) {
  while (session.current() < steps - 1) session.run_until(steps, observer);
}

class Retroactive : public ::testing::TestWithParam<std::tuple<fs::path, watch::Algorithm>> {};

TEST_P(Retroactive, WatchpointsAddedLateFindWhatTheyWouldHaveFoundFromTheStart) {
  const auto& [path, algorithm] = GetParam();
  constexpr int64_t kSteps = 50;
  Scenario fresh = load(path, algorithm);
  if (fresh.model->watches.empty()) GTEST_SKIP() << "no watchpoints";
  sim::Session straight(*fresh.model, *fresh.world, {.threads = 2, .events = fresh.events});
  std::vector<uint64_t> hashes;
  run_through(straight, kSteps,
              [&](const sim::State& s, const sim::StepOutput&) { hashes.push_back(sim::hash_state(s).whole()); });

  Scenario late = load(path, algorithm);
  std::vector<sim::HostedWatchpoint> watches = std::move(late.model->watches);
  late.model->watches.clear();
  sim::Session session(*late.model, *late.world, {.threads = 2, .events = late.events});
  session.run_until(kSteps / 2 + 3);
  ASSERT_TRUE(session.seek(kSteps / 3));
  for (sim::HostedWatchpoint& w : watches) ASSERT_TRUE(session.set_watch(std::move(w)));
  run_through(session, kSteps);

  EXPECT_EQ(sim::test::flat_matches(session), sim::test::flat_matches(straight));
  for (uint32_t w = 0; w < straight.model().watches.size(); ++w) {
    EXPECT_EQ(session.match_count(w), straight.match_count(w)) << "watch " << w;
    EXPECT_EQ(session.stats(w).created, straight.stats(w).created) << "watch " << w;
  }
  for (int64_t t = 0; t < kSteps; t += 3) {
    ASSERT_TRUE(session.seek(t));
    ASSERT_EQ(session.hash().whole(), hashes[size_t(t)]) << "step " << t;
  }
}

INSTANTIATE_TEST_SUITE_P(Shipped, Retroactive,
                         ::testing::Combine(::testing::ValuesIn(shipped()),
                                            ::testing::Values(watch::Algorithm::Centralized,
                                                              watch::Algorithm::Distributed)),
                         [](const auto& info) {
                           return std::get<0>(info.param).stem().string() + "_" +
                                  watch::algorithm_name(std::get<1>(info.param));
                         });

}  // namespace
}  // namespace dw::scenarios
