// One description of a watchpoint: its words, its compiling, its JSON and its TOML.
#include "sim/watch_spec.h"

#include <gtest/gtest.h>

namespace dw::sim {
namespace {

WatchSpec spec(std::string name, std::string text) {
  WatchSpec s;
  s.name = std::move(name);
  s.text = std::move(text);
  return s;
}

TEST(WatchSpec, ByDefaultItIsThePapersDistributedReadingLoggingWithTheDefaultBudget) {
  const WatchSpec s = spec("w", "modules(a); a.x = 1");
  EXPECT_EQ(s.options.live_budget, kDefaultMatchBudget);
  EXPECT_EQ(kDefaultMatchBudget, 20'000'000u);
  EXPECT_EQ(s.words(), "distributed chain consistent log");
  EXPECT_TRUE(s.options.optimizations.early_termination && s.options.optimizations.neighbor_culling &&
              s.options.optimizations.temporal_spans);
}

TEST(WatchSpec, EachWordSetsItsPartAndSaysWhichOne) {
  WatchSpec s;
  EXPECT_EQ(read_word(s, "centralized"), WatchWord::Algorithm);
  EXPECT_EQ(read_word(s, "any"), WatchWord::Shape);
  EXPECT_EQ(read_word(s, "simultaneous"), WatchWord::States);
  EXPECT_EQ(read_word(s, "count"), WatchWord::Action);
  EXPECT_EQ(s.algorithm, watch::Algorithm::Centralized);
  EXPECT_EQ(s.options.shape, watch::GroupShape::Any);
  EXPECT_EQ(s.options.states, watch::States::Simultaneous);
  EXPECT_EQ(s.action, MatchAction::Count);
  EXPECT_EQ(s.words(), "centralized any count") << "the centralized detector says no states";
  EXPECT_EQ(read_word(s, "modules(a);"), std::nullopt);
  // A keyed string (a trace's "shape", a scenario's shape =) takes only its part's words.
  EXPECT_EQ(read_word(s, "log", WatchWord::Shape), std::nullopt);
  EXPECT_EQ(s.action, MatchAction::Count) << "unchanged";
  EXPECT_EQ(read_word(s, "chain", WatchWord::Shape), WatchWord::Shape);
  EXPECT_EQ(std::string(word_key(WatchWord::States)), "states");
  EXPECT_EQ(word_choices(WatchWord::Action), "\"pause\", \"log\" or \"count\"");
}

TEST(WatchSpec, CompilesWithItsReadingAndGoesBackInNormalForm) {
  WatchSpec s = spec("w", "modules(a b);   (a.x = 1)  and neighbor(a, b)");
  read_word(s, "pause");
  s.options.live_budget = 7;
  auto compiled = compile(s, "run.toml");
  ASSERT_TRUE(std::holds_alternative<HostedWatchpoint>(compiled));
  const HostedWatchpoint& h = std::get<HostedWatchpoint>(compiled);
  EXPECT_EQ(h.watchpoint.name, "w");
  EXPECT_EQ(h.action, MatchAction::Pause);
  EXPECT_EQ(h.options.live_budget, 7u);
  EXPECT_EQ(h.watchpoint.source->name(), "run.toml (watch w)");
  const WatchSpec back = spec_of(h);
  EXPECT_EQ(back.text, watch::to_string(h.watchpoint.ast));
  EXPECT_EQ(back.words(), s.words());

  auto wrong = compile(spec("bad", "modules(a); a.x ="), "t.jsonl");
  ASSERT_TRUE(std::holds_alternative<watch::CompileError>(wrong));
  EXPECT_NE(std::get<watch::CompileError>(wrong).format().find("t.jsonl (watch bad)"), std::string::npos);
  auto all = compile_all(std::vector{spec("a", "modules(a); a.x = 1"), spec("bad", "modules(a); a.x =")}, "t.jsonl");
  ASSERT_TRUE(std::holds_alternative<std::string>(all));
}

TEST(WatchSpec, JsonGoesThereAndBack) {
  WatchSpec s = spec("w", "modules(a); (a.x = 1)");
  read_word(s, "centralized");
  read_word(s, "ordered");
  read_word(s, "count");
  const std::string written = to_json(s).dump();
  EXPECT_EQ(written, R"j({"name":"w","text":"modules(a); (a.x = 1)","algorithm":"centralized","shape":"ordered",)j"
                     R"("states":"consistent","action":"count"})");
  auto read = spec_from_json(nlohmann::json::parse(written));
  ASSERT_TRUE(std::holds_alternative<WatchSpec>(read)) << std::get<SpecError>(read).why;
  const WatchSpec& back = std::get<WatchSpec>(read);
  EXPECT_EQ(to_json(back).dump(), written);
  EXPECT_EQ(back.options.states, std::nullopt) << "a centralized watchpoint compares simultaneous states";
  EXPECT_EQ(back.options.live_budget, kDefaultMatchBudget);
}

TEST(WatchSpec, JsonReaderSaysWhichKeyIsWrongAndWhy) {
  const auto error = [](const std::string& text, std::span<const WatchSpec> before = {}) {
    auto read = spec_from_json(nlohmann::json::parse(text), before);
    return std::holds_alternative<SpecError>(read) ? std::get<SpecError>(read) : SpecError{"none", "none"};
  };
  const std::string good = R"("text":"modules(a); a.x = 1","algorithm":"distributed","shape":"chain",)";
  EXPECT_TRUE(error(R"({"name":"w"})").missing);
  EXPECT_EQ(error(R"({"name":"w"})").key, "text");
  EXPECT_EQ(error(R"({"name":1,)" + good + R"("states":"consistent","action":"log"})").key, "name");
  EXPECT_EQ(error(R"({"name":"12",)" + good + R"("states":"consistent","action":"log"})").key, "name");
  const std::vector<WatchSpec> before{spec("w", "modules(a); a.x = 1")};
  EXPECT_EQ(error(R"({"name":"w",)" + good + R"("states":"consistent","action":"log"})", before).why,
            "a second watchpoint named \"w\"");
  EXPECT_EQ(error(R"({"name":"w",)" + good + R"("states":"consistent","action":"shout"})").why,
            "\"action\" must be \"pause\", \"log\" or \"count\", not \"shout\"");
  const SpecError cannot =
      error(R"({"name":"w","text":"modules(a); a.x = 1","algorithm":"distributed","shape":"any","states":"consistent",)"
            R"("action":"log"})");
  EXPECT_EQ(cannot.key, "states");
  EXPECT_NE(cannot.why.find("watchpoint \"w\" cannot run: shape \"any\" needs states"), std::string::npos);
}

TEST(WatchSpec, TomlWritesEverySettingAndTheStatesOfADistributedOneOnly) {
  WatchSpec s = spec("w", "modules(a); a.x = 1");
  s.options.optimizations.neighbor_culling = false;
  std::vector<std::string> keys;
  for (const auto& [key, value] : toml_fields(s)) keys.emplace_back(key);
  EXPECT_EQ(keys, (std::vector<std::string>{"name", "text", "algorithm", "shape", "states", "action", "max_live",
                                            "early_termination", "neighbor_culling", "temporal_spans"}));
  EXPECT_EQ(std::get<int64_t>(toml_fields(s)[6].second), int64_t{kDefaultMatchBudget});
  EXPECT_EQ(std::get<bool>(toml_fields(s)[8].second), false);
  read_word(s, "centralized");
  for (const auto& [key, value] : toml_fields(s)) EXPECT_NE(key, "states");
}

}  // namespace
}  // namespace dw::sim
