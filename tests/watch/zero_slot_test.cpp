// Zero-slot watchpoints (docs/design.md §4c, `modules(); φ`): parsed, refused where they cannot act,
// explained by `check`, and decided once a step alike in every reading (watch/ensemble_detector.h),
// a match being the step with no module.
#include <gtest/gtest.h>

#include <sstream>

#include "test_ensemble.h"
#include "watch/explain.h"
#include "watch/make_detector.h"
#include "watch/parser.h"

namespace dw::watch {
namespace {

using testing::compile_or_die;
using testing::Match;
using testing::TestEnsemble;

// A ring of four holding tokens: 1, 2, 1, 0, 1 tokens at steps 0..4; module 3 absent at step 2,
// and its token unknown (no variable) at step 4.
TestEnsemble ring() {
  TestEnsemble e(4, {"token"});
  const int tokens[5][4] = {{1, 0, 0, 0}, {1, 0, 1, 0}, {0, 1, 0, -1}, {0, 0, 0, 0}, {0, 0, 1, -2}};
  for (int64_t t = 0; t < 5; ++t)
    for (uint32_t m = 0; m < 4; ++m) {
      const int v = tokens[t][m];
      if (v == -1) continue;  // absent
      std::map<std::string, int64_t> vars;
      if (v != -2) vars["token"] = v;
      e.set(t, m, vars, {(m + 1) % 4, (m + 3) % 4});
    }
  return e;
}

std::set<Match> at_steps(std::initializer_list<int64_t> steps) {
  std::set<Match> out;
  for (int64_t t : steps) out.insert({t, {}});
  return out;
}

// Every reading and shape the options allow, with every optimization combination.
void expect_in_every_reading(const TestEnsemble& e, const std::string& text, const std::set<Match>& expected) {
  const Watchpoint w = compile_or_die(text);
  ASSERT_EQ(w.program.slot_count(), 0) << text;
  for (const Optimizations& o : testing::all_optimization_combinations()) {
    for (GroupShape shape : kShapes) {
      DetectorOptions central{o, 0, shape, std::nullopt};
      EXPECT_EQ(e.run(Algorithm::Centralized, w, central), expected) << text << " centralized " << shape_name(shape);
      DetectorOptions simultaneous{o, 0, shape, States::Simultaneous};
      EXPECT_EQ(e.run(Algorithm::Distributed, w, simultaneous), expected)
          << text << " simultaneous " << shape_name(shape);
    }
    DetectorOptions consistent{o, 0, GroupShape::Chain, States::Consistent};
    EXPECT_EQ(e.run(Algorithm::Distributed, w, consistent), expected) << text << " distributed consistent";
  }
}

TEST(ZeroSlot, ParsesWithNoModuleAndPrintsBackTheSame) {
  for (const char* text :
       {"modules(); count(n in all: n.token = 1) != 1", "modules(); 1 = 1",
        "modules(); once[5](sum(n in all: n.x) > 2) and not historically[2](max(n in all: n.x) = 0)"}) {
    const Watchpoint w = compile_or_die(text);
    EXPECT_EQ(w.program.slot_count(), 0) << text;
    EXPECT_TRUE(w.ast.slots.empty()) << text;
    EXPECT_EQ(to_string(compile_or_die(to_string(w.ast)).ast), to_string(w.ast)) << text;
  }
}

TEST(ZeroSlot, WhatNeedsAModuleIsOneMistakeAtItsSpan) {
  struct Bad {
    const char* text;
    const char* message;
    uint32_t column;  // 0-based offset of the span's start
  };
  for (const Bad& b :
       {Bad{"modules(); 1 = 1 then remove a", "has no module to act on", 17},
        Bad{"modules(); count(n in all: n.x = 1) > 1 then set a.x = 1", "has no module to act on", 40},
        Bad{"modules(); a.x = 1", "'a'", 11}, Bad{"modules(); count(n in neighbors(a)) > 1", "'a'", 32}}) {
    const ParseResult r = parse(SourceText("w", b.text));
    ASSERT_EQ(r.diagnostics.size(), 1u) << b.text;
    EXPECT_NE(r.diagnostics[0].message.find(b.message), std::string::npos)
        << b.text << ": " << r.diagnostics[0].message;
    EXPECT_EQ(r.diagnostics[0].span.begin, b.column) << b.text << ": " << r.diagnostics[0].message;
  }
}

TEST(ZeroSlot, IsDecidedAtEPlusInEveryReading) {
  const Watchpoint w = compile_or_die("modules(); count(n in all: n.next.token = 1) = 0");
  EXPECT_EQ(w.program.extent_plus, 1);
  for (Algorithm a : kAlgorithms)
    for (GroupShape shape : kShapes)
      for (States states : kStates) {
        const DetectorOptions o{{}, 0, shape, states};
        EXPECT_EQ(lag(w.program, a, o), 1);
        EXPECT_EQ(make_detector(a, w, TestEnsemble(2, {"token"}).universe(), o, nullptr)->lag(), 1);
        EXPECT_EQ(make_detector(a, w, TestEnsemble(2, {"token"}).universe(), o, nullptr)->algorithm(), a);
      }
}

TEST(ZeroSlot, MatchesTheStepsWhereItHoldsInEveryReading) {
  const TestEnsemble e = ring();
  // Not exactly one token: steps 1 (two) and 3 (none); step 4 reads an unknown token (U, no match).
  expect_in_every_reading(e, "modules(); count(n in all: n.token = 1) != 1", at_steps({1, 3}));
  expect_in_every_reading(e, "modules(); count(n in all) = 3", at_steps({2}));  // module 3 absent
  expect_in_every_reading(e, "modules(); 1 = 1", at_steps({0, 1, 2, 3, 4}));
  expect_in_every_reading(e, "modules(); 1 = 2", {});
  // A window over the whole ensemble: two tokens at step 1, seen at 1..3.
  expect_in_every_reading(e, "modules(); once[2](count(n in all: n.token = 1) = 2)", at_steps({1, 2, 3}));
  // A window before step 0 is clipped: at step 0 only j = 0 is kept.
  expect_in_every_reading(e, "modules(); historically[3](sum(n in all: n.token) <= 1)", at_steps({0}));
  // Looking ahead (E+ = 1): steps 0..3 are decided, the step after 2 holds no token.
  expect_in_every_reading(e, "modules(); count(n in all: n.next.token = 1) = 0", at_steps({2}));
  // A window counting steps (j = 0..3, clipped at step 0): a token at exactly 2 of them, at step 1
  // only (steps 0 to 2 hold one, step 3 none; at step 4 the unknown token makes the count unknown).
  expect_in_every_reading(e, "modules(); times[3](count(n in all: n.token = 1) >= 1) = 2", at_steps({1}));
}

TEST(ZeroSlot, CheckExplainsIt) {
  std::ostringstream out;
  explain_watchpoint(compile_or_die("modules(); count(n in all: n.token = 1) != 1"), out);
  EXPECT_NE(out.str().find("zero-slot watchpoint on the whole ensemble"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("every reading alike"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("lag E+ = 0"), std::string::npos) << out.str();
}

}  // namespace
}  // namespace dw::watch
