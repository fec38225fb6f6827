// The runtime over several ranks (sim/runtime.cpp with a RankExchange, what crosses between them in
// sim/rank_stepping.cpp, docs/design.md §12), without MPI: the ranks are threads of this test,
// exchanging through memory. After every step, the state hash of the whole (Runtime::hash), the
// statistics and the matches equal those of one runtime.
#include <functional>

#include <gtest/gtest.h>

#include "sim/runtime.h"
#include "tests/sim/test_programs.h"
#include "tests/sim/thread_ranks.h"

namespace dw::sim {
namespace {

// What one rank saw of each step: the hash of the whole, and per watch its matches and counts.
struct Seen {
  std::vector<uint64_t> hashes, runs;  // the state hash and the run hash after each step
  std::vector<std::vector<ModuleId>> slots;
  std::vector<uint64_t> created, messages, program_messages;
  bool operator==(const Seen&) const = default;
};

// A world whose links change every step: on odd steps each module is linked to its lattice
// neighbours and to the module half the ensemble away, on even steps to the lattice's only. Over
// ranks, a block with no neighbour on another rank at step t may have had one at t - 1, along
// which agents that run a step behind (`next`) send.
class FarLinksOnOddSteps final : public World {
 public:
  void initialize(const Model& model, State& state, WorkerPool&) override {
    state.present.assign(model.module_count(), 1);
    state.graph = graph(model, 0);
  }
  void restore(const Model&, const State&) override {}
  void advance(const Model& model, State& state, std::span<const Actuation>, WorkerPool&) override {
    state.graph = graph(model, state.step);
  }

 private:
  static std::shared_ptr<const NeighborGraph> graph(const Model& model, int64_t step) {
    const NeighborGraph& lattice = *model.lattice.graph;
    const uint32_t m = lattice.module_count();
    std::vector<std::pair<ModuleId, ModuleId>> pairs;
    for (ModuleId a = 0; a < m; ++a)
      for (ModuleId b : lattice.neighbors(a)) pairs.push_back({a, b});
    if (step % 2 == 1)
      for (ModuleId a = 0; a < m / 2; ++a) pairs.push_back({a, a + m / 2});
    return std::make_shared<const NeighborGraph>(NeighborGraph::from_pairs(m, pairs));
  }
};

template <class W = StaticLatticeWorld>
Seen run(const Model& model, int steps, unsigned threads, RankExchange* ranks,
         Partition partition = Partition::Blocks) {
  W world;
  Runtime rt(model, model.watches, world, threads, ranks, partition);
  State s = rt.initial_state();
  StepOutput out;
  Seen seen;
  for (int t = 0; t < steps; ++t) {
    rt.step(s, out);
    const StateHash hash = rt.hash(s);
    seen.hashes.push_back(hash.whole());
    seen.runs.push_back(hash.run);
    seen.slots.push_back(out.watches[0].slots);
    seen.created.push_back(out.watches[0].stats.created);
    seen.messages.push_back(out.watches[0].stats.messages);
    seen.program_messages.push_back(s.program_messages);
  }
  return seen;
}

TEST(RuntimeRanks, EveryStepOfEveryRankEqualsOneRuntime) {
  // Three slots across a 9x7 hex sheet, with history (c.last) and program messages every step.
  const auto model =
      test_programs::gossip_model({LatticeKind::Hex2d, {9, 7, 1}},
                                  {{"modules(a b c); (a.v = 1) and (b.v != 1) and (c.v = 1) and (c.last.mix < a.mix)",
                                    watch::Algorithm::Distributed}});
  const Seen one = run(*model, 30, 1, nullptr);
  ASSERT_GT(one.program_messages.back(), 0u);
  size_t matched = 0;
  for (const auto& s : one.slots) matched += s.size();
  ASSERT_GT(matched, 0u) << "the watchpoint must match for the comparison to mean something";
  for (Partition partition : {Partition::Blocks, Partition::Graph})
    for (int n : {2, 3, 5})
      for (unsigned threads : {1u, 2u}) {
        const std::vector<Seen> ranks =
            on_ranks(n, [&](RankExchange& r) { return run(*model, 30, threads, &r, partition); });
        for (int r = 0; r < n; ++r)
          EXPECT_EQ(ranks[size_t(r)], one) << n << " ranks x " << threads << " threads, rank " << r
                                           << (partition == Partition::Graph ? ", blocks round-robin" : "");
      }
}

TEST(RuntimeRanks, LinksThatChangeEveryStepGiveTheResultsOfOneRuntime) {
  // b.next: the agents run a step behind the programs, and send along the links of that step. On
  // a line of 4 blocks of 4096 over 2 ranks, rank 0's block 0 has no neighbour on rank 1 at even
  // steps, and at odd ones has (the far links): its agents must count as on the border.
  const auto model = test_programs::gossip_model(
      {LatticeKind::Line, {4 * 4096, 1, 1}},
      {{"modules(a b c); (a.v = 1) and (b.next.v != 1) and (c.v = 1) and (c.last.mix < a.mix)",
        watch::Algorithm::Distributed}});
  const Seen one = run<FarLinksOnOddSteps>(*model, 20, 1, nullptr);
  size_t matched = 0;
  for (const auto& s : one.slots)
    for (size_t i = 0; i + 2 < s.size(); i += 3)
      matched += std::max(s[i], s[i + 1]) - std::min(s[i], s[i + 1]) == 2 * 4096 ||
                 std::max(s[i + 1], s[i + 2]) - std::min(s[i + 1], s[i + 2]) == 2 * 4096;
  ASSERT_GT(matched, 0u) << "some matches must run over a far link for the comparison to mean something";
  for (int n : {2, 3})
    for (unsigned threads : {1u, 2u}) {
      const std::vector<Seen> ranks =
          on_ranks(n, [&](RankExchange& r) { return run<FarLinksOnOddSteps>(*model, 20, threads, &r); });
      for (int r = 0; r < n; ++r)
        EXPECT_EQ(ranks[size_t(r)], one) << n << " ranks x " << threads << " threads, rank " << r;
    }
}

TEST(RuntimeRanks, EachRankHoldsItsOwnModulesStateOnly) {
  // 4 blocks of 4096 on a line over 3 ranks: each rank's variables, inboxes and agents are those
  // of its run of blocks, and the runs add up to the ensemble.
  const auto model =
      test_programs::gossip_model({LatticeKind::Line, {4 * 4096, 1, 1}},
                                  {{"modules(a b); (a.v = 1) and (b.v = 1)", watch::Algorithm::Distributed}});
  const size_t v = model->variable_count();
  const std::vector<std::pair<uint32_t, uint32_t>> windows = on_ranks(3, [&](RankExchange& r) {
    StaticLatticeWorld world;
    Runtime rt(*model, model->watches, world, 1, &r);
    State s = rt.initial_state();
    StepOutput out;
    for (int t = 0; t < 3; ++t) rt.step(s, out);
    EXPECT_EQ(s.values.size(), size_t{rt.module_window()} * v);
    EXPECT_EQ(s.inbox.begin.size(), size_t{rt.module_window()} * model->program_count() + 1);
    EXPECT_EQ(s.watches[0].agents->size(), rt.module_window());
    EXPECT_EQ(s.watches[0].agents->history().first(), rt.first_module());
    return std::pair(rt.first_module(), rt.module_window());
  });
  uint32_t next = 0;
  for (const auto& [first, count] : windows) {
    EXPECT_EQ(first, next);
    EXPECT_GT(count, 0u);
    EXPECT_LT(count, model->module_count());
    next = first + count;
  }
  EXPECT_EQ(next, model->module_count());
}

// On each of 3 ranks, after 3 steps: the hash of the whole, and the bytes the rank gave to
// gathers while hashing. `spoil`, when given, first changes what the rank holds.
template <class W>
std::vector<std::pair<StateHash, size_t>> hash_on_ranks(const Model& model, Partition partition,
                                                        const std::function<void(const Runtime&, State&)>& spoil = {}) {
  return on_ranks(3, [&](RankExchange& r) {
    W world;
    CountedGathers counted(r);
    Runtime rt(model, model.watches, world, 1, &counted, partition);
    State s = rt.initial_state();
    StepOutput out;
    for (int t = 0; t < 3; ++t) rt.step(s, out);
    if (spoil) spoil(rt, s);
    const size_t before = counted.gathered;
    const StateHash hash = rt.hash(s);
    return std::pair(hash, counted.gathered - before);
  });
}

// The hash of the whole is passed from rank to rank in module order: the ranks' variables and
// messages (here some 40,000 messages, 3 MB) are hashed where they are, never gathered, and the
// hash is one runtime's, whether a rank's blocks are one run or dealt round-robin.
TEST(RuntimeRanks, TheHashOfTheWholeGathersNoRanksVariablesNorMessages) {
  const auto model =
      test_programs::gossip_model({LatticeKind::Line, {4 * 4096 + 100, 1, 1}},
                                  {{"modules(a b); (a.v = 1) and (b.v = 1)", watch::Algorithm::Distributed}});
  StaticLatticeWorld world;
  Runtime one(*model, model->watches, world, 1);
  State s = one.initial_state();
  StepOutput out;
  for (int t = 0; t < 3; ++t) one.step(s, out);
  ASSERT_GT(s.inbox.messages.size(), 10'000u);
  const StateHash expected = one.hash(s);
  for (const Partition partition : {Partition::Blocks, Partition::Graph}) {
    for (const auto& [hash, gathered] : hash_on_ranks<StaticLatticeWorld>(*model, partition)) {
      EXPECT_EQ(hash, expected) << partition_name(partition);
      EXPECT_LE(gathered, 5 * 2 * sizeof(uint64_t)) << partition_name(partition) << ": only the hash passes";
    }
  }
}

// A world with a body per module, each one's records its own and changing every step.
class DriftingBodies final : public World {
 public:
  void initialize(const Model& model, State& state, WorkerPool&) override {
    const uint32_t n = model.module_count();
    state.present.assign(n, 1);
    state.graph = model.lattice.graph;
    Bodies& b = state.bodies;
    b.poses.resize(n);
    b.velocities.resize(n);
    b.local.resize(n);
    b.cluster_of.resize(n);
    b.bonds = BondSet(model.lattice.spec, false, n);
    for (ModuleId m = 0; m < n; ++m) {
      b.cluster_of.set(m, kNoCluster);
      b.poses.set(m, {.position = {float(m), 0, 0}});
      b.velocities.set(m, {.angular = {0, 0, float(m % 7)}});
      if (m % 3 == 0 && m + 1 < n) b.bonds.insert({m, m + 1});   // to a lattice neighbour
      if (m % 11 == 0 && m + 2 < n) b.bonds.insert({m, m + 2});  // listed
      if (m % 10 == 0) b.bonds.insert({m, kGround});
      if (m % 97 == 0) b.movers.push_back({.module = m, .start = m, .steps = 5, .angle = float(m)});
    }
  }
  void restore(const Model&, const State&) override {}
  void advance(const Model&, State& state, std::span<const Actuation>, WorkerPool&) override {
    for (ModuleId m = 0; m < state.bodies.poses.size(); ++m) {
      Pose p = state.bodies.poses[m];
      p.position[1] = float(state.step * (m % 5));
      state.bodies.poses.set(m, p);
    }
  }
};

// The neighbour graph and the bodies are hashed like the variables: each rank hashes its own
// modules' where they are. What a rank holds of the others' may be anything (a rank will hold only
// its own and their neighbours'), and the hash is still one runtime's; only the hash passes
// between ranks.
TEST(RuntimeRanks, EachRankHashesItsOwnModulesLinksAndBodiesOnly) {
  const auto model = test_programs::gossip_model(
      {LatticeKind::Line, {3000, 1, 1}}, {{"modules(a b); (a.v = 1) and (b.v = 1)", watch::Algorithm::Distributed}});
  DriftingBodies world;
  Runtime one(*model, model->watches, world, 1);
  State s = one.initial_state();
  StepOutput out;
  for (int t = 0; t < 3; ++t) one.step(s, out);
  const StateHash expected = one.hash(s);
  State turned = s;  // every module's records count: one velocity changed changes the hash
  turned.bodies.velocities.set(1700, {.angular = {1e-3f, 0, 0}});
  EXPECT_NE(one.hash(turned).simulation, expected.simulation);
  State cut = s;  // and so do a link, a bond and a lattice move less
  cut.graph = std::make_shared<const NeighborGraph>(s.graph->without(1700));
  EXPECT_NE(one.hash(cut).simulation, expected.simulation);
  for (const Bond& bond : {Bond{999, 1000}, Bond{1001, 1003}, Bond{1000, kGround}}) {
    cut = s;
    ASSERT_TRUE(cut.bodies.bonds.erase(bond));
    EXPECT_NE(one.hash(cut).simulation, expected.simulation);
  }
  cut = s;
  cut.bodies.movers.erase(cut.bodies.movers.begin() + 20);
  EXPECT_NE(one.hash(cut).simulation, expected.simulation);
  // What a rank holds of the modules outside its window: garbled.
  const auto spoil = [](const Runtime& rt, State& s) {
    Bodies& b = s.bodies;
    const ModuleId first = rt.first_module(), end = first + rt.module_window();
    const auto outside = [&](ModuleId m) { return m < first || m >= end; };
    for (ModuleId m = 0; m < b.poses.size(); ++m)
      if (outside(m)) {
        b.poses.set(m, {.position = {-1, -1, -1}});
        b.velocities.set(m, {.linear = {9, 9, 9}});
        b.local.set(m, {.orientation = {1, 0, 0, 0}});
        b.cluster_of.set(m, 12345);
      }
    std::vector<Bond> listed_outside;
    for (const Bond& bond : b.bonds.listed())
      if (outside(bond.a)) listed_outside.push_back(bond);
    b.bonds.erase(listed_outside);
    for (ModuleId m = 0; m < b.poses.size(); ++m)
      if (outside(m)) b.bonds.set_links(m, b.bonds.links(m) & kGroundBit);
    std::erase_if(b.movers, [&](const Mover& mover) { return outside(mover.module); });
    NeighborGraph links;  // the others' lists emptied
    for (ModuleId m = 0; m < s.graph->module_count(); ++m) {
      if (!outside(m)) links.ids.insert(links.ids.end(), s.graph->neighbors(m).begin(), s.graph->neighbors(m).end());
      links.begin.push_back(uint32_t(links.ids.size()));
    }
    s.graph = std::make_shared<const NeighborGraph>(std::move(links));
  };
  for (const Partition partition : {Partition::Blocks, Partition::Graph}) {
    for (const auto& [hash, gathered] : hash_on_ranks<DriftingBodies>(*model, partition, spoil)) {
      EXPECT_EQ(hash, expected) << partition_name(partition);
      EXPECT_LE(gathered, 5 * 4 * sizeof(uint64_t)) << partition_name(partition) << ": only the hash passes";
    }
  }
}

// What a run of SendsToStranger(modules) on a line of `length` ended with: the step and the error.
std::string failure(uint32_t length, const std::vector<ModuleId>& modules, RankExchange* ranks) {
  std::vector<std::unique_ptr<const HostProgram>> programs;
  programs.push_back(std::make_unique<test_programs::SendsToStranger>(modules));
  const auto model = std::get<std::unique_ptr<Model>>(
      build_model(make_lattice({LatticeKind::Line, {length, 1, 1}}), std::move(programs), {}, 1));
  StaticLatticeWorld world;
  Runtime rt(*model, model->watches, world, 1, ranks);
  State s = rt.initial_state();
  StepOutput out;
  try {
    for (int t = 0; t < 5; ++t) rt.step(s, out);
  } catch (const ProgramError& e) {
    return std::to_string(s.step) + ": module " + std::to_string(e.module.value_or(999)) + ": " + e.what();
  }
  return "no error";
}

TEST(RuntimeRanks, AProgramFailingOnOneRankStopsEveryRankWithItsError) {
  // The lowest failing module's error is the one, as in one process, whichever rank it is on and
  // whichever block of its rank runs first. On a line of 8, modules 5 alone, and 1 and 3 (over 4
  // ranks each is another rank's). On a line of 4 blocks of 4096 over 2 ranks, rank 0 holds
  // blocks 0 and 1: 5000 is in block 1, on the border, which runs first; 100 is inside.
  const std::pair<uint32_t, std::vector<ModuleId>> cases[] = {{8, {5}}, {8, {3, 1}}, {4 * 4096, {5000, 100}}};
  for (const auto& c : cases) {
    const uint32_t length = c.first;  // named apart: clang 14 captures no structured binding
    const std::vector<ModuleId>& modules = c.second;
    const std::string one = failure(length, modules, nullptr);
    ASSERT_NE(one.find("module " + std::to_string(std::ranges::min(modules)) + ":"), std::string::npos) << one;
    for (int n : {2, 4})
      for (const std::string& said : on_ranks(n, [&](RankExchange& r) { return failure(length, modules, &r); }))
        EXPECT_EQ(said, one) << n << " ranks, line of " << length;
  }
}

}  // namespace
}  // namespace dw::sim
