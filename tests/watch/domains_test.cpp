// Aggregates over within(m, h) and all, and argmin / argmax (docs/design.md §4c), in every reading, against a brute
// force written from §4c: the domain found by a plain breadth-first search, each slot's "now" as each reading decides
// it, a window around the aggregate clipped at step 0.
#include <gtest/gtest.h>

#include <algorithm>
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

enum class Dom { Neighbors, Within, All, Component };

// `AGG(n in DOMAIN: body) OP c`, optionally inside once[k](...), and `and a.x = v` beside it.
struct Case {
  int agg = 0;  // count, sum, min, max, argmin, argmax
  Dom dom = Dom::Neighbors;
  int root = 0, root_offset = 0, hops = 1;  // the domain's slot (0: a, 1: b) and its offset; within's h
  bool body_reads_slot = false;             // count: n.x > b.x; sum/min/max: n.x + b.x
  int body_value = 1;                       // count: n.x = body_value
  CompareOp op = CompareOp::Equal;
  int constant = 0;
  int window = 0;                  // once[window](...) around the comparison, 0: none
  bool member_reads_slot = false;  // component(m: n.x = b.x), else component(m: n.x = member_value)
  int member_value = 1;
};

std::string text(const Case& c) {
  static const char* aggs[] = {"count", "sum", "min", "max", "argmin", "argmax"};
  std::string m = c.root ? "b" : "a";
  if (c.root_offset < 0) m += ".last";
  std::string dom =
      c.dom == Dom::All      ? "all"
      : c.dom == Dom::Within ? "within(" + m + ", " + std::to_string(c.hops) + ")"
      : c.dom == Dom::Component
          ? "component(" + m + ": n.x = " + (c.member_reads_slot ? "b.x" : std::to_string(c.member_value)) + ")"
          : "neighbors(" + m + ")";
  std::string body = c.agg == 0 ? (c.body_reads_slot ? "n.x > b.x" : "n.x = " + std::to_string(c.body_value))
                                : (c.body_reads_slot ? "n.x + b.x" : "n.x");
  std::string cmp = std::string(aggs[c.agg]) + "(n in " + dom + ": " + body + ") " + spelling(c.op) + " " +
                    std::to_string(c.constant);
  if (c.window) cmp = "once[" + std::to_string(c.window) + "](" + cmp + ")";
  return "modules(a b); " + cmp;
}

Value read(const TestEnsemble& e, int64_t t, uint32_t m) {
  const auto v = e.value(t, m, "x");
  return v ? known_value(*v) : Value{};
}

// component(root: n.x = v) at s, v known or not: breadth-first from root, a candidate where the
// condition holds joins and brings its present neighbours, false stays out, unknown: unknown.
std::optional<std::vector<uint32_t>> component(const TestEnsemble& e, uint32_t root, int64_t s, Value v) {
  std::vector<uint32_t> candidates{root}, out;
  for (size_t i = 0; i < candidates.size(); ++i) {
    const Value x = read(e, s, candidates[i]);
    if (!x.known || !v.known) return std::nullopt;
    if (x.value != v.value) continue;
    out.push_back(candidates[i]);
    for (uint32_t u : e.nbrs(s, candidates[i]))
      if (e.present(s, u) && std::find(candidates.begin(), candidates.end(), u) == candidates.end())
        candidates.push_back(u);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The domain by its definition: neighbours present at s (a set), the modules 1..h hops away by a
// plain breadth-first search, or every module present at s.
std::optional<std::vector<uint32_t>> members(const TestEnsemble& e, Dom dom, int hops, uint32_t root, int64_t s) {
  if (s < 0 || s >= e.steps()) return std::nullopt;
  const uint32_t mc = e.universe().module_count();
  std::vector<uint32_t> out;
  if (dom == Dom::All) {
    for (uint32_t m = 0; m < mc; ++m)
      if (e.present(s, m)) out.push_back(m);
    return out;
  }
  if (!e.present(s, root)) return std::nullopt;
  if (dom == Dom::Neighbors) {  // a set, as recorded: a module listing itself counts itself (§4b)
    for (uint32_t u : e.nbrs(s, root))
      if (e.present(s, u)) out.push_back(u);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }
  std::vector<int> dist(mc, -1);
  dist[root] = 0;
  std::vector<uint32_t> queue{root};
  const int reach = hops;
  for (size_t i = 0; i < queue.size(); ++i) {
    const uint32_t m = queue[i];
    if (dist[m] == reach) continue;
    for (uint32_t u : e.nbrs(s, m))
      if (e.present(s, u) && dist[u] < 0) {
        dist[u] = dist[m] + 1;
        queue.push_back(u);
        out.push_back(u);
      }
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The comparison with a's "now" at ta and b's at tb (b's module bm), by §4b/§4c.
Truth compare_at(const Case& c, const TestEnsemble& e, int64_t ta, int64_t tb, uint32_t am, uint32_t bm) {
  const int64_t s = (c.dom == Dom::All ? ta : (c.root ? tb : ta)) + (c.dom == Dom::All ? 0 : c.root_offset);
  const Value member_value = c.member_reads_slot ? read(e, tb, bm) : known_value(c.member_value);
  const auto dom = s < 0 || (c.dom != Dom::All && !e.present(s, c.root ? bm : am)) ? std::nullopt
                   : c.dom == Dom::Component ? component(e, c.root ? bm : am, s, member_value)
                                             : members(e, c.dom, c.hops, c.root ? bm : am, s);
  if (!dom) return kUnknown;
  const Value b = read(e, tb, bm);
  int64_t n = 0, sum = 0, best = 0, best_id = 0;
  for (size_t i = 0; i < dom->size(); ++i) {
    const Value v = read(e, s, (*dom)[i]);
    if (!v.known || (c.body_reads_slot && !b.known)) return kUnknown;
    if (c.agg == 0) {
      n += c.body_reads_slot ? v.value > b.value : v.value == c.body_value;
      continue;
    }
    const int64_t x = v.value + (c.body_reads_slot ? b.value : 0);
    sum += x;
    // argmin and argmax: the members come by index, the ids here, so the first of equals has the least id.
    if (i == 0 || ((c.agg == 2 || c.agg == 4) ? x < best : x > best)) {
      best = x;
      best_id = (*dom)[i];
    }
  }
  if (c.agg >= 2 && dom->empty()) return kUnknown;
  const int64_t value = c.agg == 0 ? n : c.agg == 1 ? sum : c.agg >= 4 ? best_id : best;
  return truth_of(holds(c.op, value, c.constant));
}

// With the window: the or of the shifts whose reads (the aggregate's step, b.x's) fall at step 0 or later.
Truth eval(const Case& c, const TestEnsemble& e, int64_t ta, int64_t tb, uint32_t am, uint32_t bm) {
  if (!c.window) return compare_at(c, e, ta, tb, am, bm);
  const int64_t agg_step = (c.dom == Dom::All ? ta : (c.root ? tb : ta)) + (c.dom == Dom::All ? 0 : c.root_offset);
  const bool reads_b = c.body_reads_slot || (c.dom == Dom::Component && c.member_reads_slot);
  const int64_t earliest = reads_b ? std::min(agg_step, tb) : agg_step;
  Truth acc = kFalse;
  bool kept = false;
  for (int64_t j = 0; j <= c.window; ++j) {
    if (earliest - j < 0) break;
    kept = true;
    acc = kleene_or(acc, compare_at(c, e, ta - j, tb - j, am, bm));
  }
  return kept ? acc : kUnknown;
}

Case random_case(std::mt19937& rng) {
  auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<unsigned>(n)); };
  Case c;
  c.agg = pick(6);
  c.dom = static_cast<Dom>(pick(4));
  c.member_reads_slot = pick(3) == 0;
  c.member_value = pick(3);
  c.root = pick(2);
  c.root_offset = pick(4) == 0 ? -1 : 0;
  c.hops = 1 + pick(3);
  c.body_reads_slot = pick(3) == 0;
  c.body_value = pick(3);
  c.op = static_cast<CompareOp>(pick(6));
  c.constant = c.agg == 0 ? pick(5) : pick(7);
  c.window = pick(3) == 0 ? 1 + pick(2) : 0;
  return c;
}

// A random ensemble of 7 modules over 6 steps: directed links, each listed once (some to itself,
// some to absent modules), modules now and then absent, x in 0..2 and now and then lacking. Static: one topology.
TestEnsemble random_ensemble(std::mt19937& rng, bool is_static) {
  auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<unsigned>(n)); };
  const uint32_t mc = 7;
  TestEnsemble e(mc, {"x"});
  std::vector<std::vector<uint32_t>> links(mc);
  std::vector<uint8_t> here(mc, 1);
  for (int64_t t = 0; t < 6; ++t) {
    if (t == 0 || !is_static)
      for (uint32_t m = 0; m < mc; ++m) {
        links[m].clear();
        for (int i = pick(4); i > 0; --i) {
          const uint32_t u = static_cast<uint32_t>(pick(static_cast<int>(mc)));
          if (std::find(links[m].begin(), links[m].end(), u) == links[m].end()) links[m].push_back(u);
        }
        here[m] = is_static || pick(6) != 0;
      }
    for (uint32_t m = 0; m < mc; ++m) {
      if (!here[m]) continue;
      std::map<std::string, int64_t> vars;
      if (pick(12) != 0) vars["x"] = pick(3);
      e.set(t, m, vars, links[m]);
    }
  }
  e.grow(5);
  return e;
}

// Centralized (ordered: b a neighbour of a, every slot's "now" t) and distributed consistent (b a
// neighbour of a at t, filled at t + 1 and read there); on a static topology the simultaneous
// reading gives the centralized matches of its shape.
void check_against_brute_force(const Case& c, const TestEnsemble& e, bool is_static, Optimizations o) {
  const std::string watch = text(c);
  const Watchpoint w = compile_or_die(watch);
  const int64_t last = e.steps() - 1;
  std::set<Match> central, distributed;
  for (int64_t t = 0; t + w.program.extent_plus <= last; ++t)
    for (uint32_t a = 0; a < 7; ++a)
      for (uint32_t b = 0; b < 7; ++b) {
        if (a == b || !e.present(t, a)) continue;
        const auto& na = e.nbrs(t, a);
        if (std::find(na.begin(), na.end(), b) == na.end()) continue;
        if (e.present(t, b) && eval(c, e, t, t, a, b) == kTrue) central.insert({t, {a, b}});
        if (t + 1 + w.program.extent_plus <= last && e.present(t + 1, b) && eval(c, e, t, t + 1, a, b) == kTrue)
          distributed.insert({t, {a, b}});
      }
  DetectorOptions options;
  options.optimizations = o;
  EXPECT_EQ(e.run(Algorithm::Centralized, w, options), central) << watch;
  EXPECT_EQ(e.run(Algorithm::Distributed, w, options), distributed) << watch;
  if (is_static) {
    DetectorOptions simultaneous = options;
    simultaneous.states = States::Simultaneous;
    simultaneous.shape = GroupShape::Ordered;
    EXPECT_EQ(e.run(Algorithm::Distributed, w, simultaneous), central) << watch << " simultaneous";
  }
}

TEST(Domains, RandomAggregatesOverEveryDomainEqualTheirDefinitionInEveryReading) {
  std::mt19937 rng(4242);
  const std::vector<Optimizations> combinations = testing::all_optimization_combinations();
  for (int trial = 0; trial < 1000; ++trial) {
    const bool is_static = trial % 2 == 0;
    const TestEnsemble e = random_ensemble(rng, is_static);
    const Case c = random_case(rng);
    check_against_brute_force(c, e, is_static, combinations[static_cast<size_t>(trial / 2) % combinations.size()]);
  }
}

// A random ensemble as random_ensemble's whose graph mostly stays the same from step to step: at
// each step one module's links change, or one module comes or goes, or nothing does.
TestEnsemble slowly_changing_ensemble(std::mt19937& rng) {
  auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<unsigned>(n)); };
  const uint32_t mc = 7;
  TestEnsemble e(mc, {"x"});
  std::vector<std::vector<uint32_t>> links(mc);
  std::vector<uint8_t> here(mc, 1);
  auto relink = [&](uint32_t m) {
    links[m].clear();
    for (int i = pick(4); i > 0; --i) {
      const uint32_t u = static_cast<uint32_t>(pick(static_cast<int>(mc)));
      if (std::find(links[m].begin(), links[m].end(), u) == links[m].end()) links[m].push_back(u);
    }
  };
  for (uint32_t m = 0; m < mc; ++m) relink(m);
  for (int64_t t = 0; t < 8; ++t) {
    const int change = t == 0 ? 0 : pick(3);
    if (change == 1) relink(static_cast<uint32_t>(pick(static_cast<int>(mc))));
    if (change == 2) here[static_cast<size_t>(pick(static_cast<int>(mc)))] ^= 1;
    for (uint32_t m = 0; m < mc; ++m) {
      if (!here[m]) continue;
      std::map<std::string, int64_t> vars;
      if (pick(12) != 0) vars["x"] = pick(3);
      e.set(t, m, vars, links[m]);
    }
  }
  e.grow(7);
  return e;
}

// within()'s balls are kept from step to step while the graph stays the same (watch::BallCache):
// kept no longer than it does, the links copied or lent by the host (Frame::topology).
TEST(Domains, WithinKeptFromStepToStepFollowsEveryChangeOfTheGraph) {
  std::mt19937 rng(6161);
  const std::vector<Optimizations> combinations = testing::all_optimization_combinations();
  for (int trial = 0; trial < 300; ++trial) {
    TestEnsemble e = slowly_changing_ensemble(rng);
    e.lend_topology(trial % 2 == 1);
    Case c = random_case(rng);
    c.dom = Dom::Within;
    if (trial % 3 == 0) {  // the commonest form, counted without the logic (count_where)
      c.agg = 0;
      c.body_reads_slot = false;
    }
    check_against_brute_force(c, e, false, combinations[static_cast<size_t>(trial) % combinations.size()]);
  }
}

TEST(Domains, WithinExcludesItsModuleAndFollowsLinksOutward) {
  // 0 -> 1 -> 2 -> 3, and 0 lists itself; 3 -> 0 (directed).
  TestEnsemble e(4, {"x"});
  e.set(0, 0, {{"x", 1}}, {0, 1});
  e.set(0, 1, {{"x", 1}}, {2});
  e.set(0, 2, {{"x", 1}}, {3});
  e.set(0, 3, {{"x", 1}}, {0});
  auto counts = [&](const std::string& text) {
    std::set<ModuleId> at;
    for (const Match& m : e.run(Algorithm::Centralized, compile_or_die(text))) at.insert(m.second[0]);
    return at;
  };
  EXPECT_EQ(counts("modules(a); count(n in within(a, 1)) = 1"), (std::set<ModuleId>{0, 1, 2, 3}));
  EXPECT_EQ(counts("modules(a); count(n in within(a, 2)) = 2"), (std::set<ModuleId>{0, 1, 2, 3}));
  EXPECT_EQ(counts("modules(a); count(n in within(a, 8)) = 3"), (std::set<ModuleId>{0, 1, 2, 3}));
  EXPECT_EQ(counts("modules(a); count(n in neighbors(a)) = 2"), (std::set<ModuleId>{0}));  // lists itself
  EXPECT_EQ(counts("modules(a); sum(n in all: n.x) = 4"), (std::set<ModuleId>{0, 1, 2, 3}));
}

TEST(Domains, ParseErrorsAtTheirSpanOnce) {
  struct Bad {
    const char* text;
    const char* message;
  };
  for (const Bad& b : {Bad{"modules(a); count(n in within(a, 0)) > 1", "1 to 8 hops"},
                       Bad{"modules(a); count(n in within(a, 9)) > 1", "1 to 8 hops"},
                       Bad{"modules(a); count(n in within(a)) > 1", "number of hops"},
                       Bad{"modules(a); count(n in within(a, x)) > 1", "number of hops"},
                       Bad{"modules(a); count(n in within(n, 2)) > 1", "its own bound name"},
                       Bad{"modules(a); count(n in everyone) > 1", "'within(m, h)', 'all'"},
                       Bad{"modules(a); count(n in component(a)) > 1", "':' and the condition"},
                       Bad{"modules(a); count(n in component(a: count(m in all) > 1)) > 1", "do not nest"},
                       Bad{"modules(a); count(within in all) > 1", "keyword 'within'"}}) {
    const ParseResult r = parse(SourceText("w", b.text));
    ASSERT_EQ(r.diagnostics.size(), 1u) << b.text;
    EXPECT_NE(r.diagnostics[0].message.find(b.message), std::string::npos)
        << b.text << ": " << r.diagnostics[0].message;
  }
  // The new words still name variables after '.'.
  EXPECT_TRUE(
      parse(SourceText("w", "modules(a); a.within = 1 and a.all = 2 and a.argmin = a.component")).diagnostics.empty());
}

TEST(Domains, PrintAndReadBackTheSame) {
  for (const char* text : {"modules(a); count(n in within(a.last, 3): n.x = 1) > 0",
                           "modules(a); sum(n in all: n.x) != 1", "modules(a b); once[2](min(n in all: n.x) = b.x)"}) {
    const Watchpoint w = compile_or_die(text);
    EXPECT_EQ(to_string(compile_or_die(to_string(w.ast)).ast), to_string(w.ast)) << text;
  }
}

TEST(Domains, CheckExplainsDomainsAndTheirLag) {
  const Watchpoint w = compile_or_die("modules(a); count(n in within(a, 3): n.x = 1) > sum(n in all: n.x)");
  std::ostringstream out;
  explain_watchpoint(w, out);
  EXPECT_NE(out.str().find("1 to 3 hops from a"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("+3 to the distributed lags"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("every module present at the match step"), std::string::npos) << out.str();
  EXPECT_EQ(w.program.aggregate_hops, 3);
}

}  // namespace
}  // namespace dw::watch

namespace dw::watch {
namespace {

using testing::compile_or_die;
using testing::TestEnsemble;

TEST(Domains, ArgminTiesToTheLeastIdAndIsUnknownOverNone) {
  // Module 0's neighbours 1, 2, 3 with dist 5, 3, 3 (a tie); 1 to 4 have none; 5's are 4 and 0.
  TestEnsemble e(6, {"dist"});
  e.set(0, 0, {{"dist", 9}}, {1, 2, 3});
  e.set(0, 1, {{"dist", 5}}, {});
  e.set(0, 2, {{"dist", 3}}, {});
  e.set(0, 3, {{"dist", 3}}, {});
  e.set(0, 4, {{"dist", 1}}, {});
  e.set(0, 5, {{"dist", 1}}, {4, 0});
  auto at = [&](const std::string& text) {
    std::set<ModuleId> out;
    for (const testing::Match& m : e.run(Algorithm::Centralized, compile_or_die(text))) out.insert(m.second[0]);
    return out;
  };
  EXPECT_EQ(at("modules(a); argmin(n in neighbors(a): n.dist) = 2"), (std::set<ModuleId>{0}));
  EXPECT_EQ(at("modules(a); argmax(n in neighbors(a): n.dist) = 1"), (std::set<ModuleId>{0}));
  EXPECT_EQ(at("modules(a); argmax(n in neighbors(a): 0 - n.dist) = 2"), (std::set<ModuleId>{0}));
  EXPECT_EQ(at("modules(a); argmin(n in neighbors(a): n.dist) = 4"), (std::set<ModuleId>{5}));
  // Over none: unknown, so neither = nor != matches at modules 1..4.
  EXPECT_EQ(at("modules(a); argmin(n in neighbors(a): n.dist) != 99"), (std::set<ModuleId>{0, 5}));
  EXPECT_EQ(at("modules(a); argmin(n in all: n.dist) = 4"), (std::set<ModuleId>{0, 1, 2, 3, 4, 5}));
}

TEST(Domains, AnActionSetsTheArgminOfItsNeighbours) {
  TestEnsemble e(3, {"dist", "parent"});
  e.set(0, 0, {{"dist", 2}, {"parent", 0}}, {1, 2});
  e.set(0, 1, {{"dist", 1}, {"parent", 0}}, {0});
  e.set(0, 2, {{"dist", 1}, {"parent", 0}}, {0});
  const Watchpoint w = compile_or_die("modules(a); a.dist > 1 then set a.parent = argmin(n in neighbors(a): n.dist)");
  for (Algorithm algorithm : {Algorithm::Centralized, Algorithm::Distributed}) {
    std::vector<int64_t> values;
    auto d = make_detector(algorithm, w, e.universe(), {},
                           [&](int64_t, std::span<const ModuleId>, std::span<const Value> v) {
                             for (const Value& x : v) values.push_back(x.known ? x.value : -1);
                           });
    TestEnsemble::FrameData data;
    d->observe(e.frame(0, data));
    d->finish();
    EXPECT_EQ(values, (std::vector<int64_t>{1}));
  }
}

}  // namespace
}  // namespace dw::watch

namespace dw::watch {
namespace {

TEST(Domains, WhatTheWiderDomainsReadIsNamedForTheHosts) {
  using testing::compile_or_die;
  auto program = [](const char* text) { return compile_or_die(text).program; };
  for (const char* text : {"modules(a); count(n in neighbors(a)) > 1", "modules(a); a.x = 1"}) {
    EXPECT_FALSE(reads_step_snapshot(program(text))) << text;
    EXPECT_FALSE(reads_far_lists(program(text))) << text;
  }
  EXPECT_FALSE(reads_step_snapshot(program("modules(a); count(n in within(a, 2)) > 1")));
  EXPECT_TRUE(reads_far_lists(program("modules(a); count(n in within(a, 2)) > 1")));
  EXPECT_TRUE(reads_step_snapshot(program("modules(a); count(n in all) > 1")));
  EXPECT_FALSE(reads_far_lists(program("modules(a); count(n in all) > 1")));
  EXPECT_TRUE(reads_step_snapshot(program("modules(a); count(n in component(a: n.x = 1)) > 1")));
  EXPECT_TRUE(reads_far_lists(program("modules(a); count(n in component(a: n.x = 1)) > 1")));
}

}  // namespace
}  // namespace dw::watch
