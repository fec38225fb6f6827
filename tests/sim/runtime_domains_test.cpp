// The wider domains of docs/design.md §4c (`within`, `all`, `component`) read live by the modules'
// agents (sim/watch_hosting.cpp): on several blocks, threads and ranks they match what the
// centralized reading of one runtime matches. `all` and `component` read the step's snapshot with
// no lag, so their agents decide a step only once every block (and every rank) has recorded it;
// `within` reads neighbours' neighbours, past the one hop a rank's window holds.
#include <map>

#include <gtest/gtest.h>

#include "sim/runtime.h"
#include "tests/sim/test_programs.h"
#include "tests/sim/thread_ranks.h"

namespace dw::sim {
namespace {

// Per watchpoint, the slots of each decided step's matches.
using Decided = std::vector<std::map<int64_t, std::vector<ModuleId>>>;

Decided run(const Model& model, int steps, unsigned threads, RankExchange* ranks = nullptr) {
  StaticLatticeWorld world;
  Runtime rt(model, model.watches, world, threads, ranks, Partition::Blocks);
  State s = rt.initial_state();
  StepOutput out;
  Decided decided(model.watches.size());
  for (int t = 0; t < steps; ++t) {
    rt.step(s, out);
    for (size_t w = 0; w < out.watches.size(); ++w)
      if (out.watches[w].t >= 0) decided[w][out.watches[w].t] = out.watches[w].slots;
  }
  return decided;
}

// The same matches at every step both decided, each watchpoint's (those of `only`, when given).
void expect_same(const Decided& reference, const Decided& decided, const std::string& how,
                 std::vector<size_t> only = {}) {
  ASSERT_EQ(reference.size(), decided.size());
  if (only.empty())
    for (size_t w = 0; w < reference.size(); ++w) only.push_back(w);
  for (size_t w : only) {
    size_t compared = 0;
    for (const auto& [t, slots] : decided[w]) {
      const auto it = reference[w].find(t);
      EXPECT_EQ(slots, it != reference[w].end() ? it->second : std::vector<ModuleId>{})
          << how << ", watch " << w << ", step " << t;
      compared += slots.size();
    }
    EXPECT_GT(compared, 0u) << how << ", watch " << w << ": nothing matched, nothing compared";
  }
}

// 600 modules on a line (on two threads or ranks, blocks of 128), each module's v random in 0..3
// every step.
const std::vector<std::string> kTexts = {
    "modules(a); a.v = 1 and count(n in all: n.v = 3) > 150",
    "modules(a b); a.v = 0 and b.v = 1 and count(n in component(a: n.v != 3): n.v = 2) >= 2",
    "modules(a); a.v = 2 and count(n in within(a, 3): n.v = 2) >= 3",
    "modules(a b); a.v = 3 and count(n in within(b, 2): n.v = 3) = 0 and count(n in all: n.v = 0) < 150",
};

std::unique_ptr<Model> model_of(watch::Algorithm algorithm) {
  std::vector<std::pair<std::string, watch::Algorithm>> watches;
  for (const std::string& text : kTexts) watches.emplace_back(text, algorithm);
  return test_programs::gossip_model({LatticeKind::Line, {600, 1, 1}}, std::move(watches));
}

constexpr int kSteps = 14;

// One thread takes the 600 modules as one block: its agents decide once the whole step is
// recorded, as the engine does. Its one-slot watchpoints read what the centralized reading reads (a
// second slot fills a step later in the distributed reading: docs/design.md §4).
Decided one_block() {
  const Decided decided = run(*model_of(watch::Algorithm::Distributed), kSteps, 1);
  expect_same(run(*model_of(watch::Algorithm::Centralized), kSteps, 1), decided, "one block", {0, 2});
  return decided;
}

TEST(RuntimeDomains, AgentsOnSeveralBlocksMatchWhatAgentsOnOneMatch) {
  const Decided reference = one_block();
  expect_same(reference, run(*model_of(watch::Algorithm::Distributed), kSteps, 2), "2 threads");
}

TEST(RuntimeDomains, AgentsOverRanksMatchWhatAgentsInOneProcessMatch) {
  // Each rank holds its own modules' variables: `all` and `component()` read every rank's at the
  // step itself, `within()` those of modules up to three hops away.
  const Decided reference = one_block();
  const auto model = model_of(watch::Algorithm::Distributed);
  for (int n : {2, 3})
    for (unsigned threads : {1u, 2u}) {
      const std::vector<Decided> ranks = on_ranks(n, [&](RankExchange& r) { return run(*model, kSteps, threads, &r); });
      for (int r = 0; r < n; ++r)
        expect_same(reference, ranks[size_t(r)],
                    std::to_string(n) + " ranks x " + std::to_string(threads) + " threads, rank " + std::to_string(r));
    }
}

}  // namespace
}  // namespace dw::sim
