#include "sim/trace.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "sim/synthetic_trace.h"

namespace dw::sim {
namespace {

void expect_same_frames(const Trace& a, const Trace& b) {
  ASSERT_EQ(a.step_count(), b.step_count());
  ASSERT_EQ(a.universe().module_ids, b.universe().module_ids);
  ASSERT_EQ(a.universe().variables, b.universe().variables);
  for (int64_t s = 0; s < a.step_count(); ++s) {
    const watch::Frame fa = a.frame(s), fb = b.frame(s);
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
  const watch::Frame f0 = t.frame(0), f1 = t.frame(1);
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
  EXPECT_EQ(t.frame(2500000).present[0], 0);
  EXPECT_EQ(t.frame(5000000).values[0], 2);
}

TEST(Trace, TooLargeForMemoryIsAnErrorNotACrash) {
  // 3,000 steps, each naming 300 fresh neighbours: 900,000 modules in dense frames at every step.
  std::string text;
  for (int t = 0; t < 3000; ++t) {
    text += "{\"t\":" + std::to_string(t) + ",\"m\":" + std::to_string(t * 1000) + ",\"vars\":{\"x\":1},\"nbrs\":[";
    for (int i = 1; i <= 300; ++i) text += (i > 1 ? "," : "") + std::to_string(t * 1000 + i);
    text += "]}\n";
  }
  auto r = read_trace_text("wide.jsonl", text);
  ASSERT_TRUE(std::holds_alternative<std::vector<TraceError>>(r));
  const std::string message = std::get<std::vector<TraceError>>(r)[0].format();
  EXPECT_NE(message.find("wide.jsonl: error: the trace needs"), std::string::npos) << message;
  EXPECT_NE(message.find("at most 8 GiB"), std::string::npos) << message;
}

}  // namespace
}  // namespace dw::sim
