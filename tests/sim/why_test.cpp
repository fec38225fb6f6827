// Why (docs/design.md §7b): the cone of a value checked against a happens-before walk of the test's
// own over a straight run's messages, on random programs, at depths 1-4, on 1 and 2 threads and
// after seeks; outside writers named; the narrow cone dropping steady chatter; progress and cancel.
#include "sim/why.h"

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <tuple>

#include "sim/session.h"
#include "tests/sim/test_programs.h"

namespace dw::sim {
namespace {

using test_programs::gossip_model;

// What a straight run read at each step: the messages (sender, receiver) and the values after it.
struct StraightRun {
  std::vector<std::vector<std::pair<ModuleId, ModuleId>>> read;  // [step]: (from, to)
  std::vector<std::vector<int64_t>> values;                      // [step]
};

StraightRun straight_run(const Model& model, int64_t steps) {
  StaticLatticeWorld world;
  Session run(model, world, {});
  StraightRun r;
  r.read.emplace_back();  // nothing is read at step 0
  run.run_until(steps, [&](const State& s, const StepOutput&) {
    r.values.push_back(s.values);
    std::vector<std::pair<ModuleId, ModuleId>> next;
    for (const Message m : s.inbox.messages) next.emplace_back(m.from, m.to);
    r.read.push_back(std::move(next));
  });
  return r;
}

// The test's own walk: the origin of (m, column, t), then every (module, step) from which a chain
// of messages and of a module's own steps leads to it, no earlier than origin - depth.
std::set<std::pair<int64_t, ModuleId>> happens_before(const StraightRun& r, uint32_t variables, ModuleId m, int column,
                                                      int64_t t, int depth) {
  int64_t w = t;
  const auto value = [&](int64_t s) { return r.values[size_t(s)][size_t{m} * variables + size_t(column)]; };
  while (w > 0 && value(w) == value(w - 1)) --w;
  std::set<std::pair<int64_t, ModuleId>> cone{{w, m}};
  std::vector<std::pair<int64_t, ModuleId>> todo{{w, m}};
  while (!todo.empty()) {
    const auto [s, x] = todo.back();
    todo.pop_back();
    std::vector<std::pair<int64_t, ModuleId>> causes;
    if (s > 0) causes.emplace_back(s - 1, x);
    for (const auto& [from, to] : r.read[size_t(s)])
      if (to == x) causes.emplace_back(s - 1, from);
    for (const auto& c : causes)
      if (c.first >= w - depth && cone.insert(c).second) todo.push_back(c);
  }
  return cone;
}

std::set<std::pair<int64_t, ModuleId>> events_of(const Cone& cone) {
  std::set<std::pair<int64_t, ModuleId>> events;
  for (const ConeEvent& e : cone.events) events.emplace(e.step, e.module);
  return events;
}

TEST(Why, ConeEqualsAHappensBeforeWalkOnAnyThreadCountAndAfterSeeks) {
  const auto model = gossip_model({LatticeKind::Cubic, {4, 3, 3}}, {}, 7);
  const int64_t steps = 40;
  const StraightRun straight = straight_run(*model, steps);
  std::map<std::tuple<ModuleId, int, int64_t, int>, std::string> answers;
  for (unsigned threads : {1u, 2u}) {
    StaticLatticeWorld world;
    // A small budget: keyframes far apart, so that windows start between them.
    Session session(*model, world, {.threads = threads, .history_bytes = 64 << 10});
    session.run_until(steps);
    ASSERT_EQ(session.latest(), steps - 1);
    for (ModuleId m : {0u, 13u, 35u})
      for (int column : {1, 2})
        for (int64_t t : {3, 20, 39})
          for (int depth = 1; depth <= 4; ++depth) {
            session.seek((t * 7 + depth) % steps);  // wherever the cursor stands
            const int64_t at = session.current();
            const auto cone = why_value(session, m, column, t, depth, false, {});
            ASSERT_TRUE(cone);
            EXPECT_EQ(session.current(), at) << "the cursor goes back where it was";
            const auto events = events_of(*cone);
            EXPECT_EQ(events, happens_before(straight, model->variable_count(), m, column, t, depth))
                << "module " << m << " column " << column << " t " << t << " depth " << depth;
            // Every message of the cone joins two of its events.
            for (const ConeMessage& msg : cone->messages) {
              EXPECT_TRUE(events.count({msg.sent, msg.from})) << msg.from << "@" << msg.sent;
              EXPECT_TRUE(events.count({msg.read, msg.to})) << msg.to << "@" << msg.read;
              EXPECT_EQ(msg.read, msg.sent + 1);
            }
            const std::string json = cone_json(*cone, model->universe, {});
            auto [it, added] = answers.try_emplace({m, column, t, depth}, json);
            if (!added) {
              EXPECT_EQ(it->second, json) << "the same on " << threads << " threads";
            }
          }
  }
}

// Every module says the largest of its `v` and what it heard to its neighbours at every step, the
// same words again and again; module 0 changes its v once, at step 6.
class Steady final : public HostProgram {
 public:
  std::string_view name() const override { return "steady"; }
  std::vector<VariableSpec> variables() const override { return {{"v", 1}, {"heard", 0}}; }
  void step(ModuleContext& m) const override {
    int64_t v = m.get(0), heard = m.get(1);
    if (m.id() == 0 && m.step() == 6) m.set(0, v = 5);
    for (const Message msg : m.inbox()) heard = std::max(heard, msg[0]);
    m.set(1, heard);
    for (ModuleId n : m.neighbors()) m.send(n, {std::max(v, heard)});
  }
};

// A token: a module holding one passes it to the next id and lets it go; one told of it takes it
// (and passes it at the next step).
class Relay final : public HostProgram {
 public:
  std::string_view name() const override { return "relay"; }
  std::vector<VariableSpec> variables() const override { return {{"token", 0}}; }
  void step(ModuleContext& m) const override {
    const bool told = !m.inbox().empty();
    if (m.get(0) == 1) {
      for (ModuleId n : m.neighbors())
        if (n == m.id() + 1) m.send(n, {1});
      m.set(0, 0);
    }
    if (told) m.set(0, 1);
  }
};

template <class Program>
std::unique_ptr<Model> line_model(uint32_t modules) {
  std::vector<std::unique_ptr<const HostProgram>> programs;
  programs.push_back(std::make_unique<Program>());
  return std::get<std::unique_ptr<Model>>(
      build_model(make_lattice({LatticeKind::Cubic, {modules, 1, 1}}), std::move(programs), {}, 1));
}

TEST(Why, TheNarrowConeDropsSteadyChatter) {
  const auto model = line_model<Steady>(6);
  StaticLatticeWorld world;
  Session session(*model, world, {});
  session.run_until(12);
  // Module 3 hears 5 at step 9: 0 changed v at 6 and said it, 1 and 2 passed it on.
  const int heard = model->column("heard");
  const auto full = why_value(session, 3, heard, 11, 4, false, {});
  const auto narrow = why_value(session, 3, heard, 11, 4, true, {});
  ASSERT_TRUE(full && narrow);
  EXPECT_EQ(full->values[0].asked.origin, 9);
  EXPECT_EQ(full->values[0].value, 5);
  // Each kept event changed a variable, or is the origin; the chatter of the others is gone.
  const std::set<std::pair<int64_t, ModuleId>> kept{{6, 0}, {7, 1}, {8, 2}, {9, 3}};
  EXPECT_EQ(events_of(*narrow), kept);
  EXPECT_GT(full->events.size(), narrow->events.size());
  // Linked through what was dropped: each kept event's cause is the one before it in the chain.
  for (const ConeEvent& e : narrow->events) {
    if (e.step == 6) {
      EXPECT_TRUE(e.causes.empty());
      continue;
    }
    ASSERT_EQ(e.causes.size(), 1u) << e.module;
    EXPECT_EQ(narrow->events[e.causes[0]].module, e.module - 1);
  }
  ASSERT_EQ(narrow->messages.size(), 3u);  // 0 -> 1 at 6, 1 -> 2 at 7, 2 -> 3 at 8: all new
  for (const ConeMessage& m : narrow->messages) EXPECT_EQ(m.words, std::vector<int64_t>{5});
  for (const ConeMessage& m : full->messages)
    EXPECT_EQ(m.is_new, m.words == std::vector<int64_t>{5} && m.to == m.from + 1 && m.sent == 6 + m.from);
}

TEST(Why, OutsideWritersAreNamed) {
  const auto model = line_model<Relay>(8);
  StaticLatticeWorld world;
  // The scenario plants a token at module 1, step 2; the session one at module 4, step 10.
  Session session(*model, world,
                  {.events = {Intervention{.at = 2, .module = 1, .column = 0, .value = 1, .scheduled = true}}});
  session.run_until(10);
  ASSERT_EQ(session.current(), 9);
  ASSERT_EQ(session.intervene(Intervention{.module = 4, .column = 0, .value = 1}), "");
  session.run_until(16);
  // The scenario's token: module 1 passes it at 2, module 2 takes it at 3 and passes it at 4, and
  // module 3 takes it at 5.
  const auto planted = why_value(session, 3, 0, 5, 3, false, {});
  ASSERT_TRUE(planted);
  EXPECT_EQ(planted->values[0].asked.origin, 5);
  EXPECT_EQ(planted->values[0].writer, ConeEvent::Writer::Program);
  const auto root = std::find_if(planted->events.begin(), planted->events.end(),
                                 [](const ConeEvent& e) { return e.writer == ConeEvent::Writer::Event; });
  ASSERT_NE(root, planted->events.end()) << "the cone leads to the [[event]]";
  EXPECT_EQ(root->module, 1u);
  EXPECT_EQ(root->step, 2);
  EXPECT_TRUE(root->causes.empty());
  // The session's token: module 4 passes it at 10, and module 5 takes it at 11.
  const auto made = why_value(session, 5, 0, 11, 2, false, {});
  ASSERT_TRUE(made);
  EXPECT_EQ(made->values[0].asked.origin, 11);
  EXPECT_EQ(made->values[0].writer, ConeEvent::Writer::Program);
  EXPECT_TRUE(std::any_of(made->events.begin(), made->events.end(), [](const ConeEvent& e) {
    return e.writer == ConeEvent::Writer::Intervention && e.module == 4 && e.step == 10 && e.changed.size() == 1 &&
           e.changed[0].before == 0 && e.changed[0].after == 1;
  }));
  const std::string json = cone_json(*made, model->universe, {});
  EXPECT_NE(json.find("\"writer\":\"intervention\""), std::string::npos) << json;
}

TEST(Why, AValueSetFromOutsideAndLeftIsTheWritersOwn) {
  const auto model = line_model<Relay>(4);
  StaticLatticeWorld world;
  // Module 3 is last on the line: its token, once set, has no one to go to but is let go.
  Session session(*model, world, {});
  session.run_until(4);
  ASSERT_EQ(session.intervene(Intervention{.module = 0, .column = 0, .value = 7}), "");
  session.run_until(40);
  // 7 is no token to pass (the program passes 1 only): the intervention's value stays. Asked
  // soon after (its origin in the first window looked at) and long after (found further back),
  // the answer is the same.
  for (int64_t t : {7, 39}) {
    const auto set = why_value(session, 0, 0, t, 2, false, {});
    ASSERT_TRUE(set);
    EXPECT_EQ(set->values[0].asked.origin, 4);
    EXPECT_EQ(set->values[0].value, 7);
    EXPECT_EQ(set->values[0].writer, ConeEvent::Writer::Intervention);
    EXPECT_EQ(set->events[set->values[0].event].writer, ConeEvent::Writer::Intervention);
    EXPECT_TRUE(set->events[set->values[0].event].origin);
    ASSERT_EQ(set->events.size(), 1u) << t << ": an intervention is a root";
    EXPECT_TRUE(set->events[0].causes.empty());
  }
}

// A match's cone holds the cones of what its aggregate read (docs/design.md §7b, "a match's cone"),
// worked by hand on Steady's line 0-1-2-3-4-5: every heard is 1 from step 1 on, until the 5 that
// module 0 says from step 6 reaches 1 at step 7, 2 at 8, 3 at 9. At step 8, module 3 (heard 1) has
// a neighbour that heard 5: module 2. The aggregate read heard of N(3, 8) = {2, 4} at step 8 (and
// within(3, 2) also of 1 and 5); 2's value came from 0's change at step 6 through 1. At step 30,
// module 2 (v 1 since the start) has two neighbours that heard 5 (1 since step 7, 3 since step 9):
// origins far back, found in one walk for the three values.
TEST(Why, AMatchsConeHoldsWhatItsAggregateRead) {
  const auto model = line_model<Steady>(6);
  StaticLatticeWorld world;
  Session session(*model, world, {});
  session.run_until(32);
  const int heard = model->column("heard"), v = model->column("v");
  using Read = std::tuple<ModuleId, int, int64_t, int64_t>;  // module, column, t, origin
  const auto reads = [](const Cone& cone) {
    std::set<Read> got;
    for (const ConeValue& v : cone.values) got.emplace(v.asked.module, v.asked.column, v.asked.t, v.asked.origin);
    return got;
  };
  struct Case {
    std::string text;
    int64_t t;
    ModuleId a;
    std::set<Read> expected;
  };
  const Case cases[] = {
      {"modules(a); a.heard = 1 and count(n in neighbors(a): n.heard = 5) >= 1",
       8,
       3,
       {{3, heard, 8, 1}, {2, heard, 8, 8}, {4, heard, 8, 1}}},
      {"modules(a); a.heard = 1 and sum(n in within(a, 2): n.heard) > 4",
       8,
       3,
       {{3, heard, 8, 1}, {1, heard, 8, 7}, {2, heard, 8, 8}, {4, heard, 8, 1}, {5, heard, 8, 1}}},
      {"modules(a); a.v = 1 and count(n in neighbors(a): n.heard = 5) >= 2",
       30,
       2,
       {{2, v, 30, 0}, {1, heard, 30, 7}, {3, heard, 30, 9}}},
  };
  session.seek(20);
  for (const auto& [text, t, a, expected] : cases) {
    std::string why;
    const auto w = session.set_watch(
        HostedWatchpoint{test_programs::compile(text), watch::Algorithm::Centralized, MatchAction::Log, {}}, {}, &why);
    ASSERT_TRUE(w) << why;
    const MatchList& list = session.matches(*w);
    bool listed = false;
    for (size_t i = 0; i < list.size(); ++i) listed |= list.t[i] == t && list.slots[i] == a;
    ASSERT_TRUE(listed) << text << ": module " << a << " matches at step " << t;
    const std::vector<ModuleId> group{a};
    const auto cone = why_match(session, *w, t, group, 3, false, {});
    ASSERT_TRUE(cone);
    EXPECT_EQ(reads(*cone), expected) << text;
    EXPECT_EQ(session.current(), 20) << "the cursor stays";
    // 0's change at step 6, carried by 1 at 7, made 2's 5 at 8.
    const auto events = events_of(*cone);
    for (const auto& e : {std::pair<int64_t, ModuleId>{6, 0}, {7, 1}, {8, 2}})
      EXPECT_TRUE(events.count(e)) << text << ": " << e.second << "@" << e.first;
    for (const ConeEvent& e : cone->events) EXPECT_EQ(e.group, e.module == a);
    ASSERT_TRUE(session.remove_watch("w"));
  }
}

// A deep cone reports its window's steps as it records them (the protocol's progress, the window's
// bar), and a cancel stops it with the cursor where it was.
TEST(Why, ReportsItsProgressAndStopsWhenCancelled) {
  const auto model = line_model<Steady>(6);
  StaticLatticeWorld world;
  Session session(*model, world, {});
  session.run_until(12);
  session.seek(5);
  const int heard = model->column("heard");  // module 3 hears 5 at step 9 (TheNarrowConeDropsSteadyChatter)
  std::vector<std::pair<int64_t, int64_t>> reported;
  const Control watched{.progress = [&](int64_t done, int64_t total) { reported.emplace_back(done, total); }};
  const auto cone = why_value(session, 3, heard, 11, 4, false, watched);
  ASSERT_TRUE(cone);
  EXPECT_EQ(cone->values[0].asked.origin, 9);
  ASSERT_FALSE(reported.empty());
  EXPECT_EQ(reported.back().first, reported.back().second) << "the last window recorded whole";
  EXPECT_GE(reported.back().second, 6) << "steps 4 to 9 at least";
  EXPECT_EQ(session.current(), 5);
  std::stop_source stop;
  stop.request_stop();
  EXPECT_FALSE(why_value(session, 3, heard, 11, 4, false, Control{.stop = stop.get_token()}));
  EXPECT_EQ(session.current(), 5);
}

TEST(Why, WithoutHistoryThereIsNothingToLookBackInto) {
  const auto model = line_model<Relay>(4);
  StaticLatticeWorld world;
  Session session(*model, world, {.history_bytes = 0});
  session.run_until(5);
  EXPECT_FALSE(why_value(session, 1, 0, session.latest(), 3, false, {}));
  EXPECT_EQ(session.current(), 4);
}

}  // namespace
}  // namespace dw::sim
