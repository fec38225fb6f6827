// The machine model of docs/design.md §2 as the runtime implements it: reads see the previous step,
// messages arrive one step later in sender order, only neighbours can be sent to, randomness is a
// function of (seed, module, step, stream), and the recorded frames are what the watchpoints saw.
#include "sim/runtime.h"

#include <gtest/gtest.h>

#include <atomic>
#include <sstream>

#include "sim/random.h"
#include "sim/trace.h"
#include "tests/sim/test_programs.h"
#include "watch/make_detector.h"

namespace dw::sim {
namespace {

// Each module counts steps in `n`, remembers in `seen` what `n` read as, and sends its id to every
// neighbour; `first` records the sender of the first message of the inbox, `got` their number.
class Probe final : public HostProgram {
 public:
  std::string_view name() const override { return "probe"; }
  std::vector<VariableSpec> variables() const override {
    return {{"n", 10}, {"seen", -1}, {"first", -1}, {"got", 0}, {"r", 0}};
  }
  void step(ModuleContext& m) const override {
    m.set(0, m.get(0) + 1);
    m.set(1, m.get(0));  // the value before this step's assignment
    m.set(2, m.inbox().empty() ? -1 : m.inbox().front().from);
    m.set(3, static_cast<int64_t>(m.inbox().size()));
    m.set(4, static_cast<int64_t>(m.random(7) & 0xFFFF));
    for (size_t i = 1; i < m.inbox().size(); ++i) EXPECT_LT(m.inbox()[i - 1].from, m.inbox()[i].from);
    m.broadcast({static_cast<int64_t>(m.id())});
  }
};

std::unique_ptr<Model> probe_model(LatticeSpec spec, std::vector<std::unique_ptr<const HostProgram>> extra = {}) {
  std::vector<std::unique_ptr<const HostProgram>> programs;
  programs.push_back(std::make_unique<Probe>());
  for (auto& p : extra) programs.push_back(std::move(p));
  return std::get<std::unique_ptr<Model>>(build_model(make_lattice(spec), std::move(programs), {}, 5));
}

// A lattice's modules are numbered by their cells, and each has every variable: the model keeps
// no table for either (each would be as large as the ensemble, on every rank).
TEST(Runtime, FramesSayEveryModuleHasEveryVariableWithoutATable) {
  const auto model = probe_model({LatticeKind::Cubic, {3, 2, 2}});
  EXPECT_TRUE(model->universe.module_ids.empty());
  ASSERT_EQ(model->module_count(), 12u);
  for (uint32_t m = 0; m < 12; ++m) EXPECT_EQ(model->universe.id(m), m);
  StaticLatticeWorld world;
  Runtime rt(*model, model->watches, world, 1);
  State s = rt.initial_state();
  StepOutput out;
  rt.step(s, out);
  const watch::Frame frame = observed_frame(*model, s, out);
  EXPECT_TRUE(frame.has_value.empty());
  ASSERT_EQ(frame.values.size(), size_t{12} * model->variable_count());
  for (size_t at = 0; at < frame.values.size(); ++at) EXPECT_TRUE(frame.has(at)) << at;
}

TEST(Runtime, ReadsSeeThePreviousStepAndMessagesArriveOneStepLater) {
  const auto model = probe_model({LatticeKind::Line, {4, 1, 1}});
  StaticLatticeWorld world;
  Runtime rt(*model, model->watches, world, 1);
  State s = rt.initial_state();
  StepOutput out;
  rt.step(s, out);
  const uint32_t v = model->variable_count();
  EXPECT_EQ(s.values[0 * v + 0], 11);
  EXPECT_EQ(s.values[0 * v + 1], 10);
  EXPECT_EQ(s.values[2 * v + 3], 0) << "nothing arrives at step 0";
  EXPECT_EQ(out.program_messages, 6u);
  rt.step(s, out);
  EXPECT_EQ(s.values[2 * v + 3], 2) << "both neighbours' messages of step 0";
  EXPECT_EQ(s.values[2 * v + 2], 1) << "sender order: module 1 first";
  EXPECT_EQ(s.values[0 * v + 3], 1);
  EXPECT_EQ(s.step, 2);
  // Randomness is the counter-based generator's, program 0 on plain streams.
  EXPECT_EQ(s.values[3 * v + 4], static_cast<int64_t>(counter_random(5, 3, 1, 7) & 0xFFFF));
}

TEST(Runtime, ProgramsSideBySideReadOnlyTheirOwnMessages) {
  std::vector<std::unique_ptr<const HostProgram>> extra;
  extra.push_back(std::make_unique<test_programs::Gossip>());
  const auto model = probe_model({LatticeKind::Ring, {5, 1, 1}}, std::move(extra));
  EXPECT_EQ(model->variable_count(), 8u);
  EXPECT_EQ(model->program_base[1], 5u);
  StaticLatticeWorld world;
  Runtime rt(*model, model->watches, world, 1);
  State s = rt.initial_state();
  StepOutput out;
  rt.step(s, out);
  rt.step(s, out);
  const uint32_t v = model->variable_count();
  for (uint32_t m = 0; m < 5; ++m) EXPECT_EQ(s.values[m * v + 3], 2) << "probe sees only probe's messages";
  int64_t gossip_received = 0;
  for (uint32_t m = 0; m < 5; ++m) gossip_received += s.values[m * v + 7];
  EXPECT_EQ(gossip_received, 5) << "one gossip message per module, sent at step 0";
}

TEST(Runtime, SendingToAModuleThatIsNotANeighbourStopsTheRun) {
  std::vector<std::unique_ptr<const HostProgram>> programs;
  programs.push_back(std::make_unique<test_programs::SendsToStranger>());
  const auto model = std::get<std::unique_ptr<Model>>(
      build_model(make_lattice({LatticeKind::Line, {8, 1, 1}}), std::move(programs), {}, 1));
  StaticLatticeWorld world;
  Runtime rt(*model, model->watches, world, 2);
  State s = rt.initial_state();
  StepOutput out;
  rt.step(s, out);
  rt.step(s, out);
  try {
    rt.step(s, out);
    FAIL() << "expected a ProgramError";
  } catch (const ProgramError& e) {
    EXPECT_NE(std::string(e.what()).find("module 5 sent to module 7 at step 2, which is not its neighbour"),
              std::string::npos)
        << e.what();
  }
}

// Fails on every module from `first`, counting the calls made.
class FailsFrom final : public HostProgram {
 public:
  FailsFrom(ModuleId first, std::string variable, std::atomic<int>& calls)
      : first_(first), variable_(std::move(variable)), calls_(calls) {}
  std::string_view name() const override { return "fails_from"; }
  std::vector<VariableSpec> variables() const override { return {{variable_, 0}}; }
  void step(ModuleContext& m) const override {
    ++calls_;
    if (m.id() >= first_) m.fail("failed");
  }

 private:
  ModuleId first_;
  std::string variable_;
  std::atomic<int>& calls_;
};

// Once a module of a thread fails, that thread's higher modules are not called: their calls
// cannot change which failure is reported (the lowest module's), and a script looping to its
// budget on every module made the report wait for all of them. The report is the same on any
// thread count.
TEST(Runtime, AFailureSkipsTheHigherModulesCallsAndReportsTheLowest) {
  for (unsigned threads : {1u, 2u, 4u}) {
    SCOPED_TRACE(threads);
    std::atomic<int> calls{0};
    std::vector<std::unique_ptr<const HostProgram>> programs;
    programs.push_back(std::make_unique<FailsFrom>(3, "x", calls));
    programs.push_back(std::make_unique<FailsFrom>(0, "y", calls));  // never reached past module 2's first
    const auto model = std::get<std::unique_ptr<Model>>(
        build_model(make_lattice({LatticeKind::Line, {400, 1, 1}}), std::move(programs), {}, 1));
    StaticLatticeWorld world;
    Runtime rt(*model, model->watches, world, threads);
    State s = rt.initial_state();
    StepOutput out;
    try {
      rt.step(s, out);
      FAIL() << "expected a ProgramError";
    } catch (const ProgramError& e) {
      ASSERT_TRUE(e.module);
      EXPECT_EQ(*e.module, 0u);
      EXPECT_NE(std::string(e.what()).find("fails_from on module 0 failed"), std::string::npos) << e.what();
    }
    // Each thread stops at its first failing module: its first program's call and no more.
    EXPECT_LE(calls.load(), int(threads) * 2) << "not one call a module";
  }
}

// Module m sends `per_module[m]` one-word messages to its first neighbour each step.
class Floods final : public HostProgram {
 public:
  explicit Floods(std::vector<int> per_module) : per_module_(std::move(per_module)) {}
  std::string_view name() const override { return "floods"; }
  std::vector<VariableSpec> variables() const override { return {{"f", 0}}; }
  void step(ModuleContext& m) const override {
    for (int i = 0; i < per_module_[m.id()]; ++i) m.send(m.neighbors()[0], {i});
  }

 private:
  std::vector<int> per_module_;
};

// A step whose messages take more than Model::message_bytes_per_step stops the run, saying so,
// before a program sending without end takes the machine's memory. Whether it stops is the
// same on any thread count, however the senders fall to the threads: a thread past the limit
// alone means the step's messages are.
TEST(Runtime, AStepWhoseMessagesPassTheLimitStopsTheRunOnAnyThreadCount) {
  constexpr uint64_t kLimit = 24 * 1000;  // a one-word message takes 24 bytes: 1,000 messages
  const std::vector<std::pair<std::vector<int>, bool>> cases = {
      {{250, 250, 250, 250, 0, 0, 0, 0}, false},   // 1,000: at the limit, spread
      {{0, 0, 0, 0, 0, 0, 0, 1000}, false},        // 1,000 from one module
      {{200, 200, 200, 200, 201, 0, 0, 0}, true},  // 1,001: no thread alone is past it
      {{0, 0, 0, 0, 0, 0, 0, 5000000}, true},      // a flood, stopped early (5 million would take 120 MB)
  };
  for (const auto& [per_module, stops] : cases)
    for (unsigned threads : {1u, 2u, 4u}) {
      SCOPED_TRACE(testing::Message() << threads << " threads, " << (stops ? "stops" : "runs"));
      std::vector<std::unique_ptr<const HostProgram>> programs;
      programs.push_back(std::make_unique<Floods>(per_module));
      auto model = std::get<std::unique_ptr<Model>>(
          build_model(make_lattice({LatticeKind::Line, {8, 1, 1}}), std::move(programs), {}, 1));
      model->message_bytes_per_step = kLimit;
      StaticLatticeWorld world;
      Runtime rt(*model, model->watches, world, threads);
      State s = rt.initial_state();
      StepOutput out;
      std::string error;
      try {
        rt.step(s, out);
        rt.step(s, out);
      } catch (const ProgramError& e) {
        error = e.what();
      }
      if (stops) EXPECT_EQ(error.rfind("at step 0 the modules' messages took more than 24000 bytes, ", 0), 0u) << error;
      else EXPECT_EQ(error, "");
    }
}

TEST(Runtime, TwoProgramsDeclaringOneVariableIsAnError) {
  std::vector<std::unique_ptr<const HostProgram>> programs;
  programs.push_back(std::make_unique<test_programs::Gossip>());
  programs.push_back(std::make_unique<test_programs::Gossip>());
  auto built = build_model(make_lattice({LatticeKind::Line, {3, 1, 1}}), std::move(programs), {}, 1);
  ASSERT_TRUE(std::holds_alternative<std::string>(built));
  EXPECT_NE(std::get<std::string>(built).find("'v'"), std::string::npos);
}

// A program may declare no variable at all (a Lua script with `vars = {}`): the modules step,
// with no row of values to carry over (the Lua fuzzer found the runtime copying the empty rows
// from a null pointer, which the sanitizer suite stops at).
class Silent final : public HostProgram {
 public:
  std::string_view name() const override { return "silent"; }
  std::vector<VariableSpec> variables() const override { return {}; }
  void step(ModuleContext& m) const override { m.broadcast({static_cast<int64_t>(m.id())}); }
};

TEST(Runtime, AModelWithoutVariablesSteps) {
  std::vector<std::unique_ptr<const HostProgram>> programs;
  programs.push_back(std::make_unique<Silent>());
  auto model = std::get<std::unique_ptr<Model>>(
      build_model(make_lattice({LatticeKind::Line, {3, 1, 1}}), std::move(programs), {}, 1));
  ASSERT_EQ(model->variable_count(), 0u);
  StaticLatticeWorld world;
  Runtime rt(*model, model->watches, world, 1);
  State s = rt.initial_state();
  StepOutput out;
  rt.step(s, out);
  rt.step(s, out);
  EXPECT_EQ(s.step, 2);
  EXPECT_TRUE(s.values.empty());
  EXPECT_EQ(out.program_messages, 4u);  // 0 -> 1, 1 -> 0, 1 -> 2, 2 -> 1
}

// What a run records is what its watchpoints saw: replaying the recording with a detector of
// either algorithm finds exactly the live matches.
TEST(Runtime, RecordedFramesReplayToTheLiveMatches) {
  const std::string text = "modules(a b c); (a.v = 1) and (b.v != 1) and (c.v = 1) and (c.last.mix < a.mix)";
  for (auto algorithm : {watch::Algorithm::Centralized, watch::Algorithm::Distributed}) {
    const auto model = test_programs::gossip_model({LatticeKind::Hex2d, {6, 5, 1}}, {{text, algorithm}});
    StaticLatticeWorld world;
    Runtime rt(*model, model->watches, world, 2);
    State s = rt.initial_state();
    std::ostringstream recording;
    TraceWriter writer(recording, model->universe);
    std::vector<std::vector<uint32_t>> live;
    StepOutput out;
    for (int step = 0; step < 25; ++step) {
      rt.step(s, out);
      writer.write(observed_frame(*model, s, out));
      const auto& o = out.watches[0];
      for (size_t i = 0; i < o.slots.size(); i += 3)
        live.push_back({uint32_t(o.t), o.slots[i], o.slots[i + 1], o.slots[i + 2]});
    }
    ASSERT_FALSE(live.empty());
    auto read = read_trace_text("rec", recording.str());
    ASSERT_TRUE(std::holds_alternative<Trace>(read));
    const Trace& trace = std::get<Trace>(read);
    auto frames = std::get<FrameReader>(FrameReader::make(trace, std::nullopt, default_frame_budget()));
    std::vector<std::vector<uint32_t>> replayed;
    auto detector =
        watch::make_detector(algorithm, model->watches[0].watchpoint, frames.universe(), {},
                             [&](int64_t t, std::span<const watch::ModuleId> ids, std::span<const watch::Value>) {
                               for (size_t i = 0; i < ids.size(); i += 3)
                                 replayed.push_back({uint32_t(t), ids[i], ids[i + 1], ids[i + 2]});
                             });
    for (int64_t t = 0; t < trace.step_count(); ++t) detector->observe(frames.frame(t));
    std::sort(live.begin(), live.end());
    std::sort(replayed.begin(), replayed.end());
    EXPECT_EQ(live, replayed) << watch::algorithm_name(algorithm);
  }
}

}  // namespace
}  // namespace dw::sim
