#include "sim/trace.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <numeric>
#include <random>

#include "sim/synthetic_trace.h"
#include "tests/sim/trace_frames.h"

namespace dw::sim {
namespace {

void expect_same_frames(const Trace& a, const Trace& b) {
  ASSERT_EQ(a.step_count(), b.step_count());
  ASSERT_EQ(a.universe().module_ids, b.universe().module_ids);
  ASSERT_EQ(a.universe().variables, b.universe().variables);
  const test::TraceFrames framesa(a), framesb(b);
  for (int64_t s = 0; s < a.step_count(); ++s) {
    const watch::Frame &fa = framesa.frame(s), &fb = framesb.frame(s);
    EXPECT_TRUE(std::ranges::equal(fa.present, fb.present));
    EXPECT_TRUE(std::ranges::equal(fa.values, fb.values));
    EXPECT_TRUE(std::ranges::equal(fa.has_value, fb.has_value));
    EXPECT_TRUE(std::ranges::equal(fa.nbr_begin, fb.nbr_begin));
    EXPECT_TRUE(std::ranges::equal(fa.nbrs, fb.nbrs));
  }
}

TEST(Trace, WrittenTraceReadsBackIdentically) {
  CubicRandomVars spec;
  spec.nx = 3;
  spec.ny = 4;
  spec.nz = 2;
  spec.steps = 6;
  spec.maxima = {3, 1, 7, 2};
  const Trace original = make_cubic_random_vars(spec);
  const std::string path = (std::filesystem::temp_directory_path() / "dwatch_trace_roundtrip.jsonl").string();
  ASSERT_EQ(write_trace(original, path), "");
  auto read = read_trace(path);
  std::filesystem::remove(path);
  ASSERT_TRUE(std::holds_alternative<Trace>(read));
  expect_same_frames(original, std::get<Trace>(read));
}

TEST(Trace, SparseLargeIdsKeepTheirOrderAndAbsences) {
  auto r = read_trace_text("t", R"({"t":0,"m":4000000000,"vars":{"x":1},"nbrs":[7]}
{"t":1,"m":7,"vars":{"x":2},"nbrs":[4000000000]}
{"t":1,"m":4000000000,"vars":{},"nbrs":[]})");
  ASSERT_TRUE(std::holds_alternative<Trace>(r));
  const Trace& t = std::get<Trace>(r);
  EXPECT_EQ(t.universe().module_ids, (std::vector<watch::ModuleId>{7, 4000000000u}));
  const test::TraceFrames frames(t);
  const watch::Frame &f0 = frames.frame(0), &f1 = frames.frame(1);
  EXPECT_EQ(f0.present[0], 0);
  EXPECT_EQ(f0.present[1], 1);
  EXPECT_EQ(f0.neighbors(1)[0], 0u);
  EXPECT_EQ(f1.neighbors(0)[0], 1u);
  EXPECT_EQ(f1.has_value[1], 0) << "module 4000000000 lacks x at step 1";
}

TEST(Trace, StepsWithoutLinesShareOneEmptyFrame) {
  auto r = read_trace_text("t", R"({"t":0,"m":1,"vars":{"x":1},"nbrs":[]}
{"t":5000000,"m":1,"vars":{"x":2},"nbrs":[]})");
  ASSERT_TRUE(std::holds_alternative<Trace>(r));
  const Trace& t = std::get<Trace>(r);
  EXPECT_EQ(t.step_count(), 5000001);
  auto frames = std::get<FrameReader>(FrameReader::make(t, std::nullopt, default_frame_budget()));
  EXPECT_EQ(frames.frame(2500000).present[0], 0);
  EXPECT_EQ(frames.frame(5000000).values[0], 2);
}

// 3,000 steps, each naming 300 fresh neighbours: 900,000 modules. Dense frames at every step
// would take 8 GiB; the lines take what they hold, and a frame is made one step at a time.
TEST(Trace, ManyModulesCostWhatTheirLinesHold) {
  std::string text;
  for (int t = 0; t < 3000; ++t) {
    text += "{\"t\":" + std::to_string(t) + ",\"m\":" + std::to_string(t * 1000) + ",\"vars\":{\"x\":1},\"nbrs\":[";
    for (int i = 1; i <= 300; ++i) text += (i > 1 ? "," : "") + std::to_string(t * 1000 + i);
    text += "]}\n";
  }
  auto r = read_trace_text("wide.jsonl", text);
  ASSERT_TRUE(std::holds_alternative<Trace>(r));
  const Trace& t = std::get<Trace>(r);
  EXPECT_EQ(t.universe().module_count(), 903'000u);
  EXPECT_EQ(t.modules_with_lines(), 3'000u);
  auto frames = std::get<FrameReader>(FrameReader::make(t, std::nullopt, default_frame_budget()));
  const watch::Frame f = frames.frame(2999);  // module 2,999,000 is dense index 2999 x 301
  EXPECT_EQ(f.present[902'699], 1);
  EXPECT_EQ(f.neighbors(902'699).size(), 300u);
  // A frame past the budget is refused, with the option that raises it.
  auto refused = FrameReader::make(t, std::nullopt, 1e6);
  ASSERT_TRUE(std::holds_alternative<std::string>(refused));
  EXPECT_NE(std::get<std::string>(refused).find("--max-frame-memory"), std::string::npos);
}

// Twenty thousand variables, each named on one line: frames over the one variable read are small.
TEST(Trace, FramesHoldOnlyTheChosenVariables) {
  std::string text;
  for (int i = 0; i < 20000; ++i)
    text += "{\"t\":" + std::to_string(i) + ",\"m\":" + std::to_string(i % 100) + ",\"vars\":{\"v" + std::to_string(i) +
            "\":" + std::to_string(i) + "},\"nbrs\":[]}\n";
  auto r = read_trace_text("names.jsonl", text);
  ASSERT_TRUE(std::holds_alternative<Trace>(r));
  const Trace& t = std::get<Trace>(r);
  EXPECT_EQ(t.universe().variables.size(), 20000u);
  auto frames = std::get<FrameReader>(FrameReader::make(t, std::vector<std::string>{"v7", "nosuch"}, 1e6));
  EXPECT_EQ(frames.universe().variables, std::vector<std::string>{"v7"}) << "only variables the trace has";
  const watch::Frame f = frames.frame(7);
  EXPECT_EQ(f.variable_count, 1u);
  EXPECT_EQ(f.values[7], 7);
  EXPECT_EQ(f.has_value[7], 1);
  EXPECT_EQ(frames.frame(8).has_value[8], 0) << "v8 is not a column";
}

// One line with 200,000 variables reads in linear time (a quadratic reader takes minutes).
TEST(Trace, OneLineWithManyVariablesReadsInLinearTime) {
  std::string text = "{\"t\":0,\"m\":0,\"vars\":{";
  for (int i = 0; i < 200000; ++i) text += (i ? ",\"v" : "\"v") + std::to_string(i) + "\":" + std::to_string(i);
  text += "},\"nbrs\":[]}\n";
  const auto start = std::chrono::steady_clock::now();
  auto r = read_trace_text("wide.jsonl", text);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_TRUE(std::holds_alternative<Trace>(r));
  EXPECT_EQ(std::get<Trace>(r).universe().variables.size(), 200000u);
  EXPECT_LT(seconds, 20.0) << "quadratic in the variables of a line";
  // A name twice on that line is still caught, at its place.
  auto twice = read_trace_text("twice.jsonl", "{\"t\":0,\"m\":0,\"vars\":{\"a\":1,\"b\":2,\"a\":3},\"nbrs\":[]}");
  ASSERT_TRUE(std::holds_alternative<std::vector<TraceError>>(twice));
  EXPECT_EQ(std::get<std::vector<TraceError>>(twice)[0].format(),
            "twice.jsonl:1:22: error: variable 'a' appears twice");
}

// The same lines as JSON text and as columns in another order: the same trace.
TEST(Trace, ColumnsInAnyOrderGiveTheTraceTheirLinesWouldBe) {
  std::mt19937_64 random(7);
  std::string text;
  std::vector<int64_t> t, m, nbr_begin{0}, nbrs, x, y;
  std::vector<size_t> order;
  for (int64_t step = 0; step < 4; ++step)
    for (int64_t id = 0; id < 6; ++id) {
      if (random() % 5 == 0) continue;  // absent at this step
      const int64_t a = int64_t(random() % 9) - 4, b = int64_t(random() % 3);
      std::vector<int64_t> ns;
      for (int64_t n = 0; n < 7; ++n)  // 6 is named only as a neighbour
        if (n != id && random() % 3 == 0) ns.push_back(n);
      text += "{\"t\":" + std::to_string(step) + ",\"m\":" + std::to_string(id) +
              ",\"vars\":{\"x\":" + std::to_string(a) + ",\"y\":" + std::to_string(b) + "},\"nbrs\":[";
      for (size_t k = 0; k < ns.size(); ++k) text += (k ? "," : "") + std::to_string(ns[k]);
      text += "]}\n";
      t.push_back(step);
      m.push_back(id);
      x.push_back(a);
      y.push_back(b);
      nbrs.insert(nbrs.end(), ns.begin(), ns.end());
      nbr_begin.push_back(int64_t(nbrs.size()));
    }
  // Shuffled: line i of the columns is line perm[i] of the text.
  std::vector<size_t> perm(t.size());
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), random);
  Trace::Columns c;
  std::vector<int64_t> ct, cm, cb{0}, cn, cx, cy;
  for (size_t i : perm) {
    ct.push_back(t[i]);
    cm.push_back(m[i]);
    cx.push_back(x[i]);
    cy.push_back(y[i]);
    cn.insert(cn.end(), nbrs.begin() + nbr_begin[i], nbrs.begin() + nbr_begin[i + 1]);
    cb.push_back(int64_t(cn.size()));
  }
  c.t = ct, c.m = cm, c.nbr_begin = cb, c.nbrs = cn;
  c.variables = {"x", "y"};
  c.values = {cx, cy};
  auto from_columns = Trace::from_columns(c);
  auto from_text = read_trace_text("t", text);
  ASSERT_TRUE(std::holds_alternative<Trace>(from_columns)) << std::get<std::string>(from_columns);
  ASSERT_TRUE(std::holds_alternative<Trace>(from_text));
  EXPECT_EQ(std::get<Trace>(from_columns).line_count(), t.size());
  expect_same_frames(std::get<Trace>(from_text), std::get<Trace>(from_columns));
}

TEST(Trace, ColumnsAreRefusedForWhatALineIsRefusedFor) {
  const std::vector<int64_t> t{0, 1, 1}, m{3, 3, 4}, begin{0, 1, 2, 2}, nbrs{4, 4}, x{1, 2, 3};
  Trace::Columns good{t, m, begin, nbrs, {"x"}, {x}};
  ASSERT_TRUE(std::holds_alternative<Trace>(Trace::from_columns(good)));
  const auto error = [](Trace::Columns c) {
    auto r = Trace::from_columns(c);
    return std::holds_alternative<std::string>(r) ? std::get<std::string>(r) : "(accepted)";
  };
  const std::vector<int64_t> twice{1, 1, 1}, self{4, 3}, negative{0, -1, 1}, loop{0, 2, 1, 2}, repeated{4, 4, 4},
      first_twice{0, 2, 2, 2};
  Trace::Columns c = good;
  c.t = twice;
  EXPECT_EQ(error(c), "line 1 (t=1, m=3): duplicate line for module 3 at step 1 (first at line 0)");
  c = good;
  c.nbrs = self;
  EXPECT_EQ(error(c), "line 1 (t=1, m=3): module 3 lists itself as a neighbour");
  c = good;
  c.t = negative;
  EXPECT_EQ(error(c), "line 1 (t=-1, m=3): step \"t\" must be 0 or more");
  c = good;
  c.nbr_begin = loop;
  c.nbrs = repeated;
  EXPECT_EQ(error(c), "the neighbour offsets must start at 0 and end at the number of neighbours (3)");
  c = good;
  c.nbr_begin = first_twice;
  EXPECT_EQ(error(c), "line 0 (t=0, m=3): a neighbour appears twice in \"nbrs\"");
  c = good;
  c.values = {std::span<const int64_t>(x).first(2)};
  EXPECT_EQ(error(c), "variable 'x' has 2 values for 3 lines");
  c = good;
  c.variables = {"x", "x"};
  c.values = {x, x};
  EXPECT_EQ(error(c), "variable 'x' appears twice");
  c = good;
  c.m = std::span<const int64_t>(m).first(2);
  EXPECT_EQ(error(c), "\"m\" has 2 entries and \"t\" 3");
}

}  // namespace
}  // namespace dw::sim
