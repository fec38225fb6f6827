// A session saved as a scenario (scenarios/saved_scenario.cpp) is the session's branch: loaded
// again from another folder, it has the session's watchpoints with their readings and options,
// every intervention of the branch, its bookmarks, the seed, a script that still resolves, and it runs to the
// same states and matches.
#include "scenarios/saved_scenario.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <toml++/toml.h>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "sim/state.h"
#include "watch/ast.h"

namespace dw::scenarios {
namespace {

namespace fs = std::filesystem;

Scenario load(const fs::path& path, const ScenarioOverrides& overrides = {}) {
  auto loaded = load_scenario(path.string(), overrides);
  if (auto* e = std::get_if<std::string>(&loaded)) ADD_FAILURE() << *e;
  return std::move(std::get<Scenario>(loaded));
}

void run_through(sim::Session& session, int64_t steps) {
  while (session.current() < steps - 1) session.run_until(steps);
}

class SavedScenario : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dwatch_saved_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "elsewhere" / "deeper");
  }
  void TearDown() override { fs::remove_all(dir_); }
  // Writes `text` where `saved_scenario` was asked to put it, as the session's `save` does.
  static void write(const fs::path& at, const std::string& text) { std::ofstream(at) << text; }
  fs::path dir_;
};

TEST_F(SavedScenario, LoadedFromAnotherFolderItRunsTheSessionsBranch) {
  // A Lua program (a path relative to the scenario), a watchpoint of the file, the seed overridden.
  ScenarioOverrides seed;
  seed.seed = 7;
  Scenario scenario = load(fs::path(DWATCH_SCENARIOS_DIR) / "lua" / "token_ring.toml", seed);
  sim::Session session(*scenario.model, *scenario.world, {.end = 60, .history_bytes = 64 << 20});
  run_through(session, 20);
  // A watchpoint added in the session, with a budget and an optimization off, and an intervention.
  auto compiled =
      watch::compile_watchpoint("holders", watch::SourceText("t", "modules(a b); (a.token = 1) and (b.token = 0)"));
  ASSERT_TRUE(std::holds_alternative<watch::Watchpoint>(compiled));
  sim::HostedWatchpoint added{
      std::get<watch::Watchpoint>(std::move(compiled)), watch::Algorithm::Distributed, sim::MatchAction::Log, {}};
  added.options.live_budget = 123456;
  added.options.optimizations.temporal_spans = false;
  ASSERT_TRUE(session.set_watch(added));
  const int token = scenario.model->column("token");
  ASSERT_EQ(session.intervene({.kind = sim::Intervention::Kind::Set, .module = 3, .column = token, .value = 1}), "");

  // Bookmarks, one with the characters a TOML string escapes.
  sim::Bookmarks marks;
  marks.mark(12, "the token \"doubles\" here");
  marks.mark(3, "start");

  const fs::path destination = dir_ / "elsewhere" / "deeper" / "saved.toml";
  std::string error;
  const auto text = saved_scenario(scenario, session, marks, destination.string(), &error);
  ASSERT_TRUE(text) << error;
  write(destination, *text);
  Scenario saved = load(destination);

  EXPECT_EQ(saved.model->seed, 7u);
  EXPECT_EQ(saved.bookmarks, marks.all());
  EXPECT_EQ(saved.events.size(), session.interventions().size());
  for (size_t i = 0; i < saved.events.size() && i < session.interventions().size(); ++i) {
    sim::Intervention expected = session.interventions()[i];
    expected.scheduled = true;
    EXPECT_EQ(saved.events[i], expected) << "event " << i;
  }
  ASSERT_EQ(saved.model->watches.size(), session.watches().size());
  for (uint32_t w = 0; w < saved.model->watches.size(); ++w) {
    const sim::HostedWatchpoint &a = saved.model->watches[w], &b = session.watches()[w].hosted;
    EXPECT_EQ(a.watchpoint.name, b.watchpoint.name);
    EXPECT_EQ(watch::to_string(a.watchpoint.ast), watch::to_string(b.watchpoint.ast));
    EXPECT_EQ(a.algorithm, b.algorithm);
    EXPECT_EQ(a.action, b.action);
    EXPECT_EQ(a.options.live_budget, b.options.live_budget);
    EXPECT_EQ(a.options.optimizations.temporal_spans, b.options.optimizations.temporal_spans);
    EXPECT_EQ(watch::group_shape(a.algorithm, a.options), watch::group_shape(b.algorithm, b.options));
  }
  ASSERT_EQ(saved.scripts.size(), 1u);
  EXPECT_TRUE(fs::equivalent(saved.scripts[0].file, fs::path(DWATCH_SCENARIOS_DIR) / "lua" / "token_ring.lua"));

  // The same states and matches, step for step.
  sim::Session again(*saved.model, *saved.world, {.end = 60, .history_bytes = 64 << 20});
  run_through(session, 50);
  run_through(again, 50);
  EXPECT_EQ(sim::hash_state(again.state()), sim::hash_state(session.state()));
  for (uint32_t w = 0; w < saved.model->watches.size(); ++w) {
    EXPECT_EQ(again.matches(w).t, session.matches(w).t) << saved.model->watches[w].watchpoint.name;
    EXPECT_EQ(again.matches(w).slots, session.matches(w).slots) << saved.model->watches[w].watchpoint.name;
  }
}

TEST_F(SavedScenario, AWatchpointRemovedInTheSessionIsNotSaved) {
  Scenario scenario = load(fs::path(DWATCH_SCENARIOS_DIR) / "token_ring.toml");
  sim::Session session(*scenario.model, *scenario.world, {.end = 60});
  ASSERT_TRUE(session.remove_watch(scenario.model->watches.at(0).watchpoint.name));
  const fs::path destination = dir_ / "saved.toml";
  std::string error;
  const auto text = saved_scenario(scenario, session, {}, destination.string(), &error);
  ASSERT_TRUE(text) << error;
  write(destination, *text);
  EXPECT_TRUE(load(destination).model->watches.empty()) << *text;
}

// What `save` writes, `run` reads: every form a TOML string takes (''' and """ in a multi-line
// string, quotes, backslashes, control characters, a leading newline, non-ASCII) comes back as it
// was; toml++'s writer put `'''x\n'''` in a multi-line literal (`'''x` ... `''''''`), which does
// not parse. The header says where the session stood, never "at step -1".
TEST_F(SavedScenario, EveryStringFormReadsBackAsItWas) {
  const std::vector<std::string> forms = {"plain",
                                          "x'''y",
                                          "'''",
                                          "a\"b",
                                          "back\\slash",
                                          "tab\there",
                                          "cr\rx",
                                          "del\x7f",
                                          "bell\x07",
                                          "caf\xC3\xA9",
                                          "emoji \xF0\x9F\x98\x80",
                                          "quote' and '''",
                                          "ends with '",
                                          "ends with ''",
                                          "\"\"\"",
                                          "c1 \xC2\x85",
                                          "x\n'''",
                                          "'''\nx",
                                          "x\n''''''",
                                          "a\nb'",
                                          "a\nb''",
                                          "a\n\"\"\"",
                                          "a\n\"\"\"\"\"",
                                          "a\nb\\c",
                                          "a\nb\r\nc",
                                          "a\n\x01",
                                          "\n",
                                          "\n\nx",
                                          "\r\n",
                                          "x\n'''\n\"\"\"\n\\",
                                          "a\\\nb",
                                          "''\n''",
                                          ""};
  const auto basic = [](const std::string& s) {  // as a TOML basic string, every byte escaped
    std::string out = "\"";
    for (const char c : s) {
      char u[8];
      std::snprintf(u, sizeof u, "\\u%04X", unsigned(uint8_t(c)));
      out += uint8_t(c) < 0x80 && std::isalnum(uint8_t(c)) ? std::string(1, c)
             : uint8_t(c) < 0x80                           ? u
                                                           : std::string(1, c);
    }
    return out + "\"";
  };
  for (const std::string& form : forms) {
    const std::string source =
        "name = \"forms\"\ndescription = " + basic(form) +
        "\nsteps = 5\n[lattice]\nkind = \"ring\"\nsize = [4]\n[[program]]\nname = \"token_ring\"\n";
    const fs::path original = dir_ / "original.toml";
    write(original, source);
    Scenario scenario = load(original);
    sim::Session session(*scenario.model, *scenario.world, {.end = 5});
    const fs::path destination = dir_ / "saved.toml";
    std::string error;
    const auto saved = saved_scenario(scenario, session, {}, destination.string(), &error);
    ASSERT_TRUE(saved) << error;
    EXPECT_EQ(saved->find("step -1"), std::string::npos) << *saved;
    EXPECT_EQ(saved->rfind("# Saved by dwatch from " + original.string() +
                               " before step 0: its watchpoints and\n# the 0 "
                               "interventions of its branch.\n",
                           0),
              0u)
        << *saved;
    write(destination, *saved);
    auto loaded = load_scenario(destination.string(), {});
    ASSERT_TRUE(std::holds_alternative<Scenario>(loaded)) << basic(form) << ":\n"
                                                          << *saved << std::get<std::string>(loaded);
    EXPECT_EQ(toml::parse(*saved)["description"].value<std::string>(), form) << basic(form) << ":\n" << *saved;
  }
}

}  // namespace
}  // namespace dw::scenarios
