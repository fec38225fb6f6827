// Windows in time and id() (docs/design.md §4c) in every reading: where each window is clipped near
// step 0, nested windows, an empty window's unknown, and how they print and explain.
#include "watch/windows.h"

#include <gtest/gtest.h>

#include <optional>
#include <random>
#include <sstream>

#include "test_ensemble.h"
#include "watch/explain.h"
#include "watch/parser.h"

namespace dw::watch {
namespace {

using testing::compile_or_die;
using testing::Match;
using testing::TestEnsemble;

struct Reading {
  const char* name;
  Algorithm algorithm;
  DetectorOptions options;
};

std::vector<Reading> readings() {
  DetectorOptions simultaneous;
  simultaneous.states = States::Simultaneous;
  simultaneous.shape = GroupShape::Ordered;
  return {{"centralized", Algorithm::Centralized, {}},
          {"distributed", Algorithm::Distributed, {}},
          {"simultaneous", Algorithm::Distributed, simultaneous}};
}

// One module, alone, for `steps` steps, with x[t] (and, when given, y[t]).
TestEnsemble alone(const std::vector<int64_t>& x, const std::vector<int64_t>& y = {}) {
  TestEnsemble e(1, {"x", "y"});
  for (size_t t = 0; t < x.size(); ++t) {
    std::map<std::string, int64_t> vars{{"x", x[t]}};
    if (!y.empty()) vars["y"] = y[t];
    e.set(static_cast<int64_t>(t), 0, vars, {});
  }
  return e;
}

std::set<int64_t> steps_matched(const TestEnsemble& e, const std::string& text, const Reading& r) {
  std::set<int64_t> out;
  for (const Match& m : e.run(r.algorithm, compile_or_die(text), r.options)) out.insert(m.first);
  return out;
}

TEST(Windows, AWindowOfConstantsKeepsTheShiftsUpToTheMatchStep) {
  // times[3](1 = 1) is 1 at step 0, 2 at 1, 3 at 2 and 4 from step 3 on.
  const TestEnsemble e = alone({1, 2, 3, 4, 4, 4});
  for (const Reading& r : readings()) {
    EXPECT_EQ(steps_matched(e, "modules(a); times[3](1 = 1) = a.x", r), (std::set<int64_t>{0, 1, 2, 3, 4, 5}))
        << r.name;
    EXPECT_EQ(steps_matched(e, "modules(a); times[3](1 = 1) != a.x", r), (std::set<int64_t>{})) << r.name;
  }
}

TEST(Windows, ANestedWindowCountsAsReadingItsConditionAtItsOwnShiftZero) {
  // At step 0 the inner window reads a.x at step 0 alone, so the outer one keeps j = 0.
  const TestEnsemble e = alone({1, 0, 0, 0});
  for (const Reading& r : readings())
    EXPECT_EQ(steps_matched(e, "modules(a); once[2](historically[1](a.x = 1))", r), (std::set<int64_t>{0, 1, 2}))
        << r.name;
}

TEST(Windows, ALastInsideAWindowDropsTheShiftsThatWouldReadBeforeStepZero) {
  // y changes at every step: times[4](a.y != a.last.y) counts j = 0, 1 at step 2 (2 changes),
  // j = 0 at step 1, j = 0..4 from step 5 on, and at step 0 keeps no j (unknown: no count at all).
  const TestEnsemble e = alone({0, 1, 2, 3, 4, 5}, {0, 1, 2, 3, 4, 5});
  for (const Reading& r : readings()) {
    EXPECT_EQ(steps_matched(e, "modules(a); times[4](a.y != a.last.y) = a.x", r), (std::set<int64_t>{1, 2, 3, 4, 5}))
        << r.name;
    EXPECT_EQ(steps_matched(e, "modules(a); times[4](a.y != a.last.y) >= 0", r), (std::set<int64_t>{1, 2, 3, 4, 5}))
        << r.name;
  }
}

TEST(Windows, OnceHistoricallyAndSinceOverOneModule) {
  //                      t: 0  1  2  3  4  5  6
  const TestEnsemble e = alone({1, 0, 0, 0, 1, 1, 0}, {0, 1, 1, 1, 1, 0, 1});
  for (const Reading& r : readings()) {
    EXPECT_EQ(steps_matched(e, "modules(a); once[2](a.x = 1)", r), (std::set<int64_t>{0, 1, 2, 4, 5, 6})) << r.name;
    EXPECT_EQ(steps_matched(e, "modules(a); historically[2](a.y = 1)", r), (std::set<int64_t>{3, 4})) << r.name;
    // ψ = (x = 1) at some step of the last 3, and y = 1 at every step after it.
    EXPECT_EQ(steps_matched(e, "modules(a); since[2](a.y = 1, a.x = 1)", r), (std::set<int64_t>{0, 1, 2, 4, 5, 6}))
        << r.name;
  }
}

TEST(Windows, AnUnboundedSinceIsKeptAsABitAStep) {
  //                      t: 0  1  2  3  4  5  6
  const TestEnsemble e = alone({1, 0, 0, 0, 1, 1, 0}, {0, 1, 0, 1, 1, 0, 1});
  for (const Reading& r : readings()) {
    EXPECT_EQ(steps_matched(e, "modules(a); since(a.y = 1, a.x = 1)", r), (std::set<int64_t>{0, 1, 4, 5, 6})) << r.name;
    EXPECT_EQ(steps_matched(e, "modules(a); not since(a.y = 1, a.x = 1)", r), (std::set<int64_t>{2, 3})) << r.name;
    // Read one step back, by a window around it: S(t) or S(t - 1).
    EXPECT_EQ(steps_matched(e, "modules(a); not once[1](since(a.y = 1, a.x = 1))", r), (std::set<int64_t>{3}))
        << r.name;
    // With a.last inside it starts at step 1 (S(0) = F): unknown at step 0.
    EXPECT_EQ(steps_matched(e, "modules(a); since(a.y = 1, a.last.x = 1)", r), (std::set<int64_t>{1, 5, 6})) << r.name;
    EXPECT_EQ(steps_matched(e, "modules(a); not since(a.y = 1, a.last.x = 1)", r), (std::set<int64_t>{2, 3, 4}))
        << r.name;
    // With a.next inside, the bit of step t is known once step t + 1 is.
    EXPECT_EQ(steps_matched(e, "modules(a); since(a.y = 1, a.next.x = 1)", r), (std::set<int64_t>{3, 4})) << r.name;
  }
}

TEST(Windows, AnUnboundedSinceOverTheSecondSlotReadsAtItsStep) {
  TestEnsemble e(2, {"x"});
  for (int64_t t = 0; t < 4; ++t) {
    e.set(t, 0, {{"x", 0}}, {1});
    e.set(t, 1, {{"x", t == 1 ? 1 : 0}}, {0});
  }
  // b.x = 1 at step 1 only: since(b.x = 0, b.x = 1) holds from step 1 on, at b's own step.
  const Watchpoint w = compile_or_die("modules(a b); since(b.x = 0, b.x = 1) and id(a) = 0");
  EXPECT_EQ(e.run(Algorithm::Centralized, w), (std::set<Match>{{1, {0, 1}}, {2, {0, 1}}, {3, {0, 1}}}));
  EXPECT_EQ(e.run(Algorithm::Distributed, w), (std::set<Match>{{0, {0, 1}}, {1, {0, 1}}, {2, {0, 1}}}));
}

TEST(Windows, AWindowWithNoShiftKeptIsUnknown) {
  const TestEnsemble e = alone({1, 1, 1});
  for (const Reading& r : readings()) {
    // At step 0 a.last.x is before step 0: no j is kept, neither the window nor its negation holds.
    EXPECT_EQ(steps_matched(e, "modules(a); once[1](a.last.x = 1)", r), (std::set<int64_t>{1, 2})) << r.name;
    EXPECT_EQ(steps_matched(e, "modules(a); not once[1](a.last.x = 1)", r), (std::set<int64_t>{})) << r.name;
    EXPECT_EQ(steps_matched(e, "modules(a); not historically[1](a.last.x = 2)", r), (std::set<int64_t>{1, 2}))
        << r.name;
  }
}

TEST(Windows, InTheDistributedReadingAWindowOverTheSecondSlotIsClippedAtItsOwnStep) {
  // Two neighbours; b fills one step after a, so at t0 = 0 a window over b alone reads from step 1.
  TestEnsemble e(2, {"x"});
  for (int64_t t = 0; t < 4; ++t) {
    e.set(t, 0, {{"x", 0}}, {1});
    e.set(t, 1, {{"x", 0}}, {0});
  }
  const Watchpoint w = compile_or_die("modules(a b); times[3](b.x = 0) = 2");
  // Centralized: 1 at step 0, 2 at step 1. Distributed: b's step is t0 + 1, so 2 at t0 = 0.
  EXPECT_EQ(e.run(Algorithm::Centralized, w), (std::set<Match>{{1, {0, 1}}, {1, {1, 0}}}));
  EXPECT_EQ(e.run(Algorithm::Distributed, w), (std::set<Match>{{0, {0, 1}}, {0, {1, 0}}}));
}

TEST(Windows, IdReadsTheModulesIdWhenItIsPresent) {
  TestEnsemble e(3, {"x"});
  e.set(0, 0, {{"x", 0}}, {1});
  e.set(0, 1, {{"x", 1}}, {0, 2});
  e.set(0, 2, {{"x", 7}}, {1});
  e.set(1, 1, {{"x", 1}}, {});
  for (const Reading& r : readings()) {
    EXPECT_EQ(steps_matched(e, "modules(a); a.x = id(a)", r), (std::set<int64_t>{0, 1})) << r.name;
    // Module 1 at step 1: id(a.last) is 1; module 0 is absent at step 1.
    EXPECT_EQ(steps_matched(e, "modules(a); id(a.last) = 1", r), (std::set<int64_t>{1})) << r.name;
    EXPECT_EQ(steps_matched(e, "modules(a); count(n in neighbors(a): id(n) > id(a)) = 1", r), (std::set<int64_t>{0}))
        << r.name;
  }
  const Watchpoint w = compile_or_die("modules(a b); id(b) = id(a) + 1");
  EXPECT_EQ(e.run(Algorithm::Centralized, w), (std::set<Match>{{0, {0, 1}}, {0, {1, 2}}}));
  EXPECT_EQ(e.run(Algorithm::Distributed, w), (std::set<Match>{{0, {0, 1}}}));  // b fills at step 1: only 1's there
}

TEST(Windows, PrintAndReadBackTheSame) {
  for (const char* text : {"modules(a b); once[3]((a.x = 2)) and historically[2]((b.y = 1))",
                           "modules(a b); since[3]((b.x != 0), (a.x = 2)) or (times[4]((b.y != b.last.y)) >= 2)",
                           "modules(a); (id(a.last) = times[2](once[1]((a.x = 1))))", "modules(a); (a.id = a.once)"}) {
    const SourceText source("w", text);
    const ParseResult r = parse(source);
    ASSERT_TRUE(r.ok()) << text;
    EXPECT_EQ(to_string(r.ast), text);
  }
}

TEST(Windows, CheckSaysEachWindowsReach) {
  std::ostringstream out;
  explain_watchpoint(compile_or_die("modules(a); times[20](a.parent != a.last.parent) > 3"), out);
  EXPECT_NE(out.str().find("times[20]((a.parent != a.last.parent))\n      j = 0..20; reach 21 steps back"),
            std::string::npos)
      << out.str();
}

TEST(Windows, CheckSaysAnUnboundedSinceIsKeptIncrementally) {
  std::ostringstream out;
  explain_watchpoint(compile_or_die("modules(a); a.isLeader = 1 and not since(a.isLeader = 1, a.won = 1)"), out);
  EXPECT_NE(out.str().find("unbounded: each module keeps it as one bit a step"), std::string::npos) << out.str();
}

TEST(Windows, TheReachCountsTowardTheOffsetLimit) {
  const SourceText ok("w", "modules(a); once[9999](a.last.x = 1)");
  EXPECT_TRUE(parse(ok).ok());
  const SourceText far("w", "modules(a); once[9999](a.last.last.x = 1)");
  const ParseResult r = parse(far);
  ASSERT_EQ(r.diagnostics.size(), 1u);
  EXPECT_NE(r.diagnostics[0].message.find("reaches 10001 steps back"), std::string::npos) << r.diagnostics[0].message;
  const SourceText nested("w", "modules(a); once[6000](historically[5000](a.x = 1))");
  EXPECT_EQ(parse(nested).diagnostics.size(), 1u);
}

}  // namespace
}  // namespace dw::watch

namespace dw::watch {
namespace {

// A brute force written from docs/design.md §4c over one slot: random conditions of windows (nested,
// with `last` and `next` inside), evaluated by their definition with the clipping rule, against
// every reading's matches.
struct Term {
  enum Kind { Compare, Not, And, Or, Once, Historically, Since, Times } kind = Compare;
  int offset = 0, value = 0, k = 0;  // Compare: a.x at offset = value; Times: count = value
  std::vector<Term> kids;
};

std::string text(const Term& e) {
  auto module = [](int offset) {
    std::string m = "a";
    for (int i = 0; i < offset; ++i) m += ".next";
    for (int i = 0; i > offset; --i) m += ".last";
    return m;
  };
  const std::string k = "[" + std::to_string(e.k) + "]";
  switch (e.kind) {
    case Term::Compare: return "(" + module(e.offset) + ".x = " + std::to_string(e.value) + ")";
    case Term::Not: return "not (" + text(e.kids[0]) + ")";
    case Term::And: return "(" + text(e.kids[0]) + " and " + text(e.kids[1]) + ")";
    case Term::Or: return "(" + text(e.kids[0]) + " or " + text(e.kids[1]) + ")";
    case Term::Once: return "once" + k + "(" + text(e.kids[0]) + ")";
    case Term::Historically: return "historically" + k + "(" + text(e.kids[0]) + ")";
    case Term::Since: return "since" + (e.k ? k : "") + "(" + text(e.kids[0]) + ", " + text(e.kids[1]) + ")";
    case Term::Times: return "(times" + k + "(" + text(e.kids[0]) + ") = " + std::to_string(e.value) + ")";
  }
  return "";
}

// The earliest offset a term reads at its shift 0 (a window counts as its condition's), if any.
std::optional<int> earliest(const Term& e) {
  if (e.kind == Term::Compare) return e.offset;
  std::optional<int> m;
  for (const Term& c : e.kids)
    if (auto o = earliest(c)) m = m ? std::min(*m, *o) : *o;
  return m;
}

Truth eval(const Term& e, const TestEnsemble& ens, int64_t t) {
  if (e.kind == Term::Compare) {
    const auto v = ens.value(t + e.offset, 0, "x");
    return v ? truth_of(*v == e.value) : kUnknown;
  }
  if (e.kind == Term::Not) return kleene_not(eval(e.kids[0], ens, t));
  if (e.kind == Term::And) return kleene_and(eval(e.kids[0], ens, t), eval(e.kids[1], ens, t));
  if (e.kind == Term::Or) return kleene_or(eval(e.kids[0], ens, t), eval(e.kids[1], ens, t));
  const int64_t last = t + earliest(e).value_or(0);  // the deepest j kept (unbounded for a since)
  const int64_t top = e.kind == Term::Since && e.k == 0 ? last : std::min<int64_t>(e.k, last);
  if (top < 0) return kUnknown;
  Truth acc = e.kind == Term::Historically ? kTrue : kFalse;
  int64_t count = 0;
  bool unknown = false;
  for (int64_t j = 0; j <= top; ++j) {
    const Truth x = eval(e.kids[0], ens, t - j);
    if (e.kind == Term::Once) acc = kleene_or(acc, x);
    if (e.kind == Term::Historically) acc = kleene_and(acc, x);
    if (e.kind == Term::Times) count += x == kTrue, unknown |= x == kUnknown;
    if (e.kind == Term::Since) {
      Truth held = eval(e.kids[1], ens, t - j);
      for (int64_t i = 0; i < j; ++i) held = kleene_and(held, eval(e.kids[0], ens, t - i));
      acc = kleene_or(acc, held);
    }
  }
  if (e.kind == Term::Times) return unknown ? kUnknown : truth_of(count == e.value);
  return acc;
}

Term random_term(std::mt19937& rng, int depth, bool own_only) {
  auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<unsigned>(n)); };
  Term e;
  if (depth == 0 || pick(3) == 0) {
    e.offset = pick(3) - 1 - (pick(4) == 0);  // -2..1
    e.value = pick(2);
    return e;
  }
  e.kind = static_cast<Term::Kind>(1 + pick(7));
  e.k = 1 + pick(3);
  if (e.kind == Term::Since && own_only && pick(2) == 0) e.k = 0;
  e.value = pick(3);
  const int kids = e.kind == Term::And || e.kind == Term::Or || e.kind == Term::Since ? 2 : 1;
  for (int i = 0; i < kids; ++i) e.kids.push_back(random_term(rng, depth - 1, own_only));
  if (e.kind == Term::Since && e.k == 0 && earliest(e).value_or(0) > 0) e.k = 2;  // refused: reads only ahead
  return e;
}

TEST(Windows, RandomWindowsEqualTheirDefinitionInEveryReading) {
  std::mt19937 rng(6161);
  for (int trial = 0; trial < 1500; ++trial) {
    std::vector<int64_t> x;
    for (int t = 0; t < 9; ++t) x.push_back(static_cast<int64_t>(rng() % 2));
    TestEnsemble e(1, {"x"});
    for (int t = 0; t < 9; ++t)
      if (trial % 5 != 0 || t != 4) e.set(t, 0, {{"x", x[static_cast<size_t>(t)]}}, {});  // absent at 4 now and then
    e.grow(8);
    const Term term = random_term(rng, 3, true);
    const std::string watch = "modules(a); " + text(term);
    const Watchpoint w = compile_or_die(watch);
    std::set<int64_t> want;
    for (int64_t t = 0; t + w.program.extent_plus <= 8; ++t)
      if (e.present(t, 0) && eval(term, e, t) == kTrue) want.insert(t);
    std::string xs;
    for (int t = 0; t < 9; ++t) xs += e.present(t, 0) ? std::to_string(x[static_cast<size_t>(t)]) : "-";
    for (const Reading& r : readings())
      EXPECT_EQ(steps_matched(e, watch, r), want) << watch << " " << r.name << " x " << xs;
  }
}

}  // namespace
}  // namespace dw::watch

namespace dw::watch {
namespace {

TEST(Windows, AWindowOverOneModuleIsKeptByItNotWrittenOutOverItsShifts) {
  // §4c Costs: a window of 6,000 steps over one module's own variables costs what one of 2 does.
  const Watchpoint small = compile_or_die("modules(a); times[2](historically[3](a.x = 1)) > 1");
  const Watchpoint large = compile_or_die("modules(a); times[6000](historically[4000](a.x = 1)) > 1");
  EXPECT_EQ(large.ast.nodes.size(), small.ast.nodes.size());
  ASSERT_EQ(large.program.kept_windows.size(), 2u);
  EXPECT_EQ(large.program.kept_windows[0].kind, WindowKind::Historically);  // the inner one first
  EXPECT_EQ(large.program.kept_windows[1].k, 6000);
  // A window reading a second module is written out: its cost is its length.
  const Watchpoint two = compile_or_die("modules(a b); once[50](a.x = b.x)");
  EXPECT_TRUE(two.program.kept_windows.empty());
  EXPECT_GT(two.ast.nodes.size(), 50u);
}

TEST(Windows, ALongKeptWindowEqualsItsDefinitionOverManySteps) {
  // 400 steps of x, absent now and then: once, historically, times and since over windows of 1
  // to 150 steps against a brute force of their definition (the clipping near step 0 included).
  constexpr int kSteps = 400;
  std::mt19937 rng(4242);
  std::vector<std::optional<int64_t>> x(kSteps);
  TestEnsemble e(1, {"x"});
  for (int t = 0; t < kSteps; ++t) {
    if (rng() % 17 != 0) x[static_cast<size_t>(t)] = static_cast<int64_t>(rng() % 5 != 0);
    if (x[static_cast<size_t>(t)]) e.set(t, 0, {{"x", *x[static_cast<size_t>(t)]}}, {});
  }
  e.grow(kSteps - 1);
  auto phi = [&](int64_t s) {
    return x[static_cast<size_t>(s)] ? truth_of(*x[static_cast<size_t>(s)] == 1) : kUnknown;
  };
  for (int k : {1, 7, 150}) {
    const std::string n = std::to_string(k);
    std::set<int64_t> once, hist, times, since;
    for (int64_t t = 0; t < kSteps; ++t) {
      if (!e.present(t, 0)) continue;
      Truth o = kFalse, h = kTrue, s = kFalse;
      int64_t count = 0;
      bool unknown = false;
      for (int64_t j = 0; j <= std::min<int64_t>(k, t); ++j) {
        o = kleene_or(o, phi(t - j));
        h = kleene_and(h, phi(t - j));
        count += phi(t - j) == kTrue;
        unknown |= phi(t - j) == kUnknown;
        Truth held = kleene_not(phi(t - j));  // since(x = 1, x != 1)
        for (int64_t i = 0; i < j; ++i) held = kleene_and(held, phi(t - i));
        s = kleene_or(s, held);
      }
      if (o == kTrue) once.insert(t);
      if (h == kTrue) hist.insert(t);
      if (!unknown && count == k / 2) times.insert(t);
      if (s == kTrue) since.insert(t);
    }
    for (const Reading& r : readings()) {
      EXPECT_EQ(steps_matched(e, "modules(a); once[" + n + "](a.x = 1)", r), once) << k << r.name;
      EXPECT_EQ(steps_matched(e, "modules(a); historically[" + n + "](a.x = 1)", r), hist) << k << r.name;
      EXPECT_EQ(steps_matched(e, "modules(a); times[" + n + "](a.x = 1) = " + std::to_string(k / 2), r), times)
          << k << r.name;
      EXPECT_EQ(steps_matched(e, "modules(a); since[" + n + "](a.x = 1, a.x != 1)", r), since) << k << r.name;
    }
  }
}

}  // namespace
}  // namespace dw::watch
