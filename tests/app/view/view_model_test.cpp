// The debugger's view model and Readout without a window: the camera, the timeline's mapping, what
// each key and click sends to the session, the matches table's filter and order, and the Readout's
// panels read from a real session.
#include "app/view/view_model.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <numeric>

#include "app/view/readout.h"
#include "scenarios/scenario.h"

namespace dw::view {
namespace {

TEST(OrbitCamera, LooksWhereTheCameraItCameFromLooks) {
  render::Camera c;
  c.eye = {4, -7, 9};
  c.target = {1, 2, -1};
  const OrbitCamera o = OrbitCamera::looking(c);
  const render::Camera back = o.camera();
  EXPECT_NEAR(glm::distance(back.eye, c.eye), 0, 1e-4);
  EXPECT_NEAR(glm::distance(back.target, c.target), 0, 1e-6);
}

TEST(OrbitCamera, OrbitKeepsTheDistancePanMovesTheTargetZoomStopsShort) {
  OrbitCamera o;
  o.distance = 20;
  const glm::vec3 eye = o.eye();
  o.orbit(100, 0);
  EXPECT_NEAR(glm::distance(o.eye(), o.target), 20, 1e-4);
  EXPECT_GT(glm::distance(o.eye(), eye), 1);
  o.orbit(0, 100000);  // straight up is as far as it goes
  EXPECT_NEAR(o.pitch, glm::radians(89.0f), 1e-5);
  const glm::vec3 target = o.target;
  o.pan(100, 0, 500);
  EXPECT_GT(glm::distance(o.target, target), 0.5f);
  EXPECT_NEAR(o.target.z, target.z, 0.5f);  // seen from above, a sideways drag moves across the ground
  for (int i = 0; i < 1000; ++i) o.zoom(1);
  EXPECT_GE(o.distance, 0.5f);
}

TEST(Timeline, StepsAndPixelsMapBothWays) {
  const Timeline t{0, 199, 100, 400};
  for (int64_t s : {0, 1, 57, 198, 199}) EXPECT_EQ(t.step_at(t.x_of(s)), s) << s;
  EXPECT_EQ(t.step_at(0), 0);       // left of the timeline: the first step
  EXPECT_EQ(t.step_at(1e6f), 199);  // right of it: the last
  EXPECT_FLOAT_EQ(t.x_of(0), 101);  // the middle of step 0's two pixels
}

TEST(Timeline, LaneDensityCountsMatchesPerColumn) {
  const Timeline t{0, 99, 0, 10};
  const std::vector<int64_t> steps = {0, 0, 5, 9, 10, 55, 99, 150};
  const std::vector<uint32_t> d = lane_density(steps, t, 10);
  ASSERT_EQ(d.size(), 10u);
  EXPECT_EQ(d[0], 4u);  // steps 0, 0, 5, 9
  EXPECT_EQ(d[1], 1u);
  EXPECT_EQ(d[5], 1u);
  EXPECT_EQ(d[9], 1u);  // 150 is past the timeline
  EXPECT_EQ(std::accumulate(d.begin(), d.end(), 0u), 7u);
  // The same as counting each step's column one by one, for a lane wider than the steps too.
  for (const Timeline& t2 : {Timeline{0, 999, 5, 300}, Timeline{20, 60, 0, 700}}) {
    std::vector<int64_t> many;
    for (int64_t s = 0; s < 1000; s += 1 + s % 7) many.push_back(s);
    std::vector<uint32_t> one_by_one(size_t(t2.width), 0);
    for (int64_t s : many)
      if (s >= t2.first && s <= t2.last) one_by_one[size_t((t2.x_of(s) - t2.x0) / t2.width * t2.width)]++;
    EXPECT_EQ(lane_density(many, t2, int(t2.width)), one_by_one);
  }
}

TEST(Matches, NextAndPreviousSkipTheCurrentStep) {
  const std::vector<int64_t> steps = {3, 3, 8, 20};
  EXPECT_EQ(next_match(steps, 3), 8);
  EXPECT_EQ(next_match(steps, 0), 3);
  EXPECT_EQ(next_match(steps, 20), std::nullopt);
  EXPECT_EQ(previous_match(steps, 8), 3);
  EXPECT_EQ(previous_match(steps, 3), std::nullopt);
}

// The timeline starts fitted to what exists and follows it; zoom and pan stay within the steps.
TEST(TimelineRange, FittedToTheSimulatedStepsZoomedAboutTheMouseAndPannedWithinTheRun) {
  TimelineRange r;
  EXPECT_EQ(r.shown({2, 3, 200}), std::make_pair(int64_t{0}, int64_t{3 + TimelineRange::kMinSpan}))
      << "3 of 200 steps simulated: not the scenario's 200";
  EXPECT_EQ(r.shown({150, 160, 200}), std::make_pair(int64_t{0}, int64_t{180}));
  EXPECT_EQ(r.shown({150, 199, 200}), std::make_pair(int64_t{0}, int64_t{199}));
  EXPECT_EQ(r.shown({150, 300, 200}).second, 300) << "past the end: up to the latest";
  const Position at{100, 199, 200};
  r.zoom(0.5, 50, at);  // about step 50, at a quarter of 0..199
  EXPECT_FALSE(r.fitted);
  auto [first, last] = r.shown(at);
  EXPECT_NEAR(double(last - first), 99.5, 1.0);
  EXPECT_NEAR(double(50 - first) / double(last - first), 50.0 / 199.0, 0.02) << "step 50 stays under the mouse";
  r.pan(-1000, at);
  EXPECT_EQ(r.shown(at).first, 0) << "not before step 0";
  EXPECT_NEAR(double(r.shown(at).second), 99.5, 1.0) << "the span is kept";
  r.pan(1000, at);
  EXPECT_EQ(r.shown(at).second, 199) << "not past the end";
  for (int i = 0; i < 40; ++i) r.zoom(0.5, 150, at);
  EXPECT_EQ(r.shown(at).second - r.shown(at).first, TimelineRange::kMinSpan) << "the deepest zoom";
  for (int i = 0; i < 40; ++i) r.zoom(2.0, 150, at);
  EXPECT_EQ(r.shown(at), std::make_pair(int64_t{0}, int64_t{199})) << "zoomed out: the whole run, no further";
  r.show(20, 10, at);
  EXPECT_EQ(r.shown(at).second - r.shown(at).first, TimelineRange::kMinSpan) << "a reversed range: the smallest";
  r.fit();
  EXPECT_EQ(r.shown({2, 3, 200}).second, 3 + TimelineRange::kMinSpan);
}

// The panels tile the window, leave the 3D view most of it, and know when it is too small.
TEST(PanelLayout, TilesTheWindowAtEverySize) {
  for (const auto& [w, h] : {std::pair{1600.0f, 1000.0f}, {1024.0f, 640.0f}, {2560.0f, 1440.0f}, {900.0f, 600.0f}}) {
    const PanelLayout l = panel_layout(0, 20, w, h);
    const PanelRect rects[] = {l.view, l.transport, l.watchpoints, l.matches, l.module, l.statistics};
    float area = 0;
    for (const PanelRect& r : rects) {
      EXPECT_GE(r.x, 0) << w;
      EXPECT_GE(r.y, 20) << w;
      EXPECT_LE(r.x + r.width, w + 0.01f) << w;
      EXPECT_LE(r.y + r.height, 20 + h + 0.01f) << w;
      EXPECT_GT(r.height, 60) << w << "x" << h;
      area += r.width * r.height;
    }
    EXPECT_NEAR(area, w * h, 1.0f) << "the panels cover the window once: " << w << "x" << h;
    EXPECT_EQ(l.view.width, l.transport.width);
    EXPECT_GE(l.view.width, w * 0.55f);
    EXPECT_EQ(l.too_small, w < 1024 || h < 640);
    if (!l.too_small) {
      EXPECT_GE(l.view.height, 380) << w << "x" << h;
    }
  }
}

TEST(ViewModel, KeysSendTheSessionCommands) {
  ViewModel m;
  const Position at{10, 40, 200};
  const std::vector<int64_t> steps = {5, 12, 90};
  EXPECT_EQ(m.on_key(Key::Right, at, steps), std::vector<std::string>{"step 1"});
  EXPECT_EQ(m.on_key(Key::Left, at, steps), std::vector<std::string>{"seek 9"});
  EXPECT_TRUE(m.on_key(Key::Left, {0, 40, 200}, steps).empty());  // nothing before step 0
  EXPECT_EQ(m.on_key(Key::N, at, steps), std::vector<std::string>{"seek 12"});
  EXPECT_EQ(m.on_key(Key::P, at, steps), std::vector<std::string>{"seek 5"});
  // A match past the latest step: the session runs there.
  EXPECT_EQ(m.on_key(Key::N, {12, 40, 200}, steps), std::vector<std::string>{"run 90"});
  EXPECT_EQ(m.on_key(Key::End, at, steps), std::vector<std::string>{"seek 40"});
  // No match known after the current step: N runs on to the chosen watchpoint's next one.
  EXPECT_TRUE(m.on_key(Key::N, {90, 120, 200}, steps).empty());
  EXPECT_EQ(m.on_key(Key::N, {90, 120, 200}, steps, "two_leaders"),
            std::vector<std::string>{"run --to-match two_leaders"});
  EXPECT_FALSE(m.playing);
  m.on_key(Key::Space, at, steps);
  EXPECT_TRUE(m.playing);
  m.on_key(Key::Right, at, steps);
  EXPECT_FALSE(m.playing) << "stepping pauses";
  m.camera_placed = true;
  m.on_key(Key::F, at, steps);
  EXPECT_FALSE(m.camera_placed) << "F fits the camera again";
  m.on_key(Key::Z, at, steps);
  EXPECT_FALSE(m.focus_selection) << "nothing selected to centre on";
  m.selected = 3;
  m.on_key(Key::Z, at, steps);
  EXPECT_TRUE(m.focus_selection);
}

// T follows the selection and T again stops; F (the whole ensemble) stops it too. Key names are
// read in any case (the README writes F1).
TEST(ViewModel, TFollowsTheSelectionAndKeysAreNamedInAnyCase) {
  ViewModel m;
  const Position at{10, 40, 200};
  m.on_key(Key::T, at, {});
  EXPECT_FALSE(m.followed) << "nothing selected to follow";
  m.selected = 4;
  m.on_key(Key::T, at, {});
  EXPECT_EQ(m.followed, sim::ModuleId(4));
  m.on_key(Key::T, at, {});
  EXPECT_FALSE(m.followed);
  m.on_key(Key::T, at, {});
  m.on_key(Key::F, at, {});
  EXPECT_FALSE(m.followed) << "F fits the whole ensemble";
  EXPECT_EQ(key_named("F1"), Key::F1);
  EXPECT_EQ(key_named("f1"), Key::F1);
  EXPECT_EQ(key_named("T"), Key::T);
  EXPECT_FALSE(key_named("f13"));
  EXPECT_FALSE(key_named("f1x"));
}

TEST(ViewModel, TimelineClicksSeekOrRun) {
  ViewModel m;
  const Timeline t{0, 199, 0, 200};
  EXPECT_EQ(m.on_timeline_click(t, t.x_of(30), {10, 40, 200}), std::vector<std::string>{"seek 30"});
  EXPECT_EQ(m.on_timeline_click(t, t.x_of(120), {10, 40, 200}), std::vector<std::string>{"run 120"});
  EXPECT_TRUE(m.on_timeline_click(t, t.x_of(10), {10, 40, 200}).empty());
}

TEST(ViewModel, PlayingAsksForStepsAtItsSpeed) {
  ViewModel m;
  m.speed = 30;
  EXPECT_EQ(m.steps_due(0.01), 0);
  EXPECT_EQ(m.steps_due(0.1), 3);
  m.speed = 0;
  EXPECT_EQ(m.steps_due(0.0), 1);
}

TEST(Commands, AreLinesOfTheSessionLanguage) {
  EXPECT_EQ(command::set(7, "token", -3), "set 7 token -3");
  EXPECT_EQ(command::push(2, {0.5f, 0, -1.25f}), "push 2 0.5 0 -1.25");
  EXPECT_EQ(command::watch("w", "centralized pause", "modules(a);\n(a.x = 1)"),
            "watch w centralized pause modules(a); (a.x = 1)");
}

TEST(WindowCommands, AreCheckedWithTheirColumn) {
  auto check = [](const std::string& line) -> std::string {
    std::vector<ScriptWord> words;
    for (size_t i = 0; i < line.size();) {
      if (line[i] == ' ') {
        ++i;
        continue;
      }
      const size_t from = i;
      while (i < line.size() && line[i] != ' ') ++i;
      words.push_back({line.substr(from, i - from), {uint32_t(from), uint32_t(i)}});
    }
    const auto d = check_window_command(words, 10, {uint32_t(line.size()), uint32_t(line.size() + 1)});
    return d ? std::to_string(d->span.begin) + ": " + d->message : "ok";
  };
  EXPECT_EQ(check("click 9"), "ok");
  EXPECT_EQ(check("click 10"), "6: M must be an integer from 0 to 9");
  EXPECT_EQ(check("click match 3"), "ok");
  EXPECT_EQ(check("click timeline"), "14: T is missing");
  EXPECT_EQ(check("key f12"), "ok");
  EXPECT_EQ(check("key F12"), "ok") << "as the README writes it";
  EXPECT_EQ(check("key F13").substr(0, 16), "4: key NAME: one");
  EXPECT_EQ(check("follow 9"), "ok");
  EXPECT_EQ(check("follow off"), "ok");
  EXPECT_EQ(check("follow"), "6: M (or off) is missing");
  EXPECT_EQ(check("wait -1"), "5: N must be an integer from 0 to 100000");
  EXPECT_EQ(check("screenshot"), "10: screenshot FILE: the PNG to write");
  EXPECT_EQ(check("panel inspector"), "ok");
  EXPECT_EQ(
      check("panel stats"),
      "6: panel NAME: position, matches, watchpoints, inspector, group, plots, timeline, widgets, pointers or why");
  EXPECT_EQ(check("panel matches x"), "14: 'panel' takes 1 more word");
  EXPECT_EQ(check("timeline fit"), "ok");
  EXPECT_EQ(check("timeline 10 20"), "ok");
  EXPECT_EQ(check("timeline 10"), "11: LAST is missing");
  EXPECT_EQ(check("timeline"), "8: timeline fit | timeline FIRST LAST: the steps the timeline shows");
  EXPECT_EQ(check("timeline 1 2 3"), "13: 'timeline' takes 2 more words");
  EXPECT_TRUE(is_window_command("click"));
  EXPECT_FALSE(is_window_command("seek"));
}

// A real session: leader election run to its pause.
struct Leader : ::testing::Test {
  void SetUp() override {
    auto loaded = scenarios::load_scenario(std::string(DWATCH_SCENARIOS_DIR) + "/leader_election.toml");
    ASSERT_TRUE(std::holds_alternative<scenarios::Scenario>(loaded));
    scenario = std::make_unique<scenarios::Scenario>(std::move(std::get<scenarios::Scenario>(loaded)));
    session = std::make_unique<sim::Session>(*scenario->model, *scenario->world,
                                             sim::SessionOptions{1, scenario->steps, 64 << 20, scenario->events});
    pause = session->run_until(scenario->steps);
    ASSERT_TRUE(pause);
  }
  std::unique_ptr<scenarios::Scenario> scenario;
  std::unique_ptr<sim::Session> session;
  std::optional<sim::Pause> pause;
};

TEST_F(Leader, TheMatchesTableFiltersByModuleAndSorts) {
  const sim::MatchList& list = session->matches(0);
  const size_t k = 3;
  const sim::ModuleId m = pause->group[1];
  const MatchRows all = filter_matches(*session, {}, 1'000'000);
  EXPECT_EQ(all.total, list.size());
  MatchFilter only;
  only.module = m;
  const MatchRows rows = filter_matches(*session, only, 1'000'000);
  size_t holding = 0;
  for (size_t i = 0; i < list.size(); ++i)
    holding += std::count(list.slots.begin() + i * k, list.slots.begin() + (i + 1) * k, m) > 0;
  EXPECT_EQ(rows.total, holding);
  for (const MatchRef& r : rows.rows)
    EXPECT_NE(std::find(list.slots.begin() + r.index * k, list.slots.begin() + (r.index + 1) * k, m),
              list.slots.begin() + (r.index + 1) * k);
  MatchFilter latest_first;
  latest_first.descending = true;
  const MatchRows desc = filter_matches(*session, latest_first, 5);
  EXPECT_EQ(desc.rows.size(), std::min<size_t>(5, list.size()));
  EXPECT_EQ(desc.total, list.size());
  for (size_t i = 1; i < desc.rows.size(); ++i) EXPECT_GE(list.t[desc.rows[i - 1].index], list.t[desc.rows[i].index]);
}

TEST_F(Leader, AMatchClickSeeksToItsStepAndSelectsItsGroup) {
  ViewModel view;
  const auto [first, last] = session->matches(0).at(pause->t);
  ASSERT_LT(first, last);
  EXPECT_EQ(view.on_match_click(*session, {0, first}), std::vector<std::string>{"seek " + std::to_string(pause->t)});
  EXPECT_EQ(view.selected, pause->group[0]);
  EXPECT_TRUE(view.reveal_group);
  EXPECT_FALSE(view.focus_selection) << "a match chosen does not re-centre the camera";

  // The Readout highlights that group, and the inspector shows the module's values.
  const auto window = read_module_window(*session, *view.selected, 100);
  ASSERT_TRUE(window);
  const Timeline timeline{0, session->latest(), 0, 50};
  const Readout readout = read_readout(*session, *scenario, view, {1, &*window, timeline, 50});
  // The timeline's lane counts every match of the history once, in the column of its step.
  const std::vector<uint32_t>& lane = readout.watches[0].lane;
  ASSERT_EQ(lane.size(), 50u);
  EXPECT_EQ(std::accumulate(lane.begin(), lane.end(), size_t{0}), session->matches(0).size());
  EXPECT_EQ(lane, lane_density(session->matches(0).t, timeline, 50));
  // Seen from the step the session is on (the pause), the next match is ahead of it or none.
  for (int64_t s : readout.watches[0].nearest_steps) EXPECT_NE(s, pause->t);
  ASSERT_EQ(readout.scene.groups.size(), 1u);
  EXPECT_EQ(readout.scene.groups[0].modules, pause->group);
  ASSERT_TRUE(readout.inspector);
  const nlohmann::ordered_json panel = readout.panel("inspector", *scenario->model);
  EXPECT_EQ(panel["module"], pause->group[0]);
  const int leader = scenario->model->column("isLeader");
  EXPECT_EQ(readout.inspector->variables[size_t(leader)].value, 1) << "slot a of two_leaders is a leader";
  EXPECT_EQ(readout.inspector->plot.size(), size_t(session->latest() + 1)) << "the whole history";
  EXPECT_EQ(readout.panel("nosuch", *scenario->model).count("error"), 1u);
}

// A script's runtime error, as the window shows it: the position panel names the step and the
// module until the run moves on, here after the script is fixed and loaded again.
TEST(ProgramFailure, IsShownAtItsStepUntilTheRunMovesOn) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("dwatch_failure_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string header = "program = { vars = { \"v\" } }\n";
  std::ofstream(dir / "x.lua") << header +
                                      "function step(m)\n  if m.step == 6 and m.id == 2 then error('boom') end\nend\n";
  std::ofstream(dir / "s.toml")
      << "steps = 20\n[lattice]\nkind = \"line\"\nsize = [4]\n[[program]]\nscript = \"x.lua\"\n";
  auto loaded = scenarios::load_scenario((dir / "s.toml").string());
  ASSERT_TRUE(std::holds_alternative<scenarios::Scenario>(loaded)) << std::get<std::string>(loaded);
  scenarios::Scenario& scenario = std::get<scenarios::Scenario>(loaded);
  sim::Session session(*scenario.model, *scenario.world, {1, scenario.steps});
  EXPECT_THROW(session.run_until(20), sim::ProgramError);
  ViewModel view;
  nlohmann::ordered_json position = read_readout(session, scenario, view, {}).panel("position", *scenario.model);
  ASSERT_TRUE(position.contains("failure")) << position.dump();
  EXPECT_EQ(position["failure"]["step"], 6);
  EXPECT_EQ(position["failure"]["module"], 2);
  EXPECT_NE(position["failure"]["message"].get<std::string>().find("x.lua:3: boom"), std::string::npos);
  EXPECT_EQ(position["latest"], 5) << "the run stands at the last step that went through";

  std::ofstream(dir / "x.lua") << header + "function step(m) m:set(\"v\", m.step) end\n";
  ASSERT_TRUE(std::holds_alternative<std::vector<std::string>>(scenarios::reload_scripts(scenario, session)));
  EXPECT_FALSE(read_readout(session, scenario, view, {}).panel("position", *scenario.model).contains("failure"));
  session.run_until(20);
  EXPECT_EQ(session.state().values[2], 19);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace dw::view

namespace dw::view {
namespace {

// The status line says what a command did in words, never as the answer's JSON.
TEST(AnswerWords, APauseASeekAndASaveReadAsSentences) {
  const auto paused = nlohmann::ordered_json::parse(
      R"({"cmd":"run","current":1,"latest":3,"decided":1,"paused":{"watch":"two_leaders","t":1,"detected":3,"group":{"a":7,"b":6,"c":17},"matches":91}})");
  EXPECT_EQ(answer_words(paused),
            "paused at step 1 on two_leaders: a=7 b=6 c=17 (found at step 3), 91 matches at that step");
  const auto seek = nlohmann::ordered_json::parse(R"({"cmd":"seek 2","current":2,"latest":3,"decided":3})");
  EXPECT_EQ(answer_words(seek), "seek: done; at step 2 (0 to 3 simulated)");
  const auto save =
      nlohmann::ordered_json::parse(R"({"cmd":"save x.toml","save":"x.toml","watches":2,"interventions":1})");
  EXPECT_EQ(answer_words(save), "saved the session as x.toml (2 watchpoints, 1 intervention)");
  const auto matched = nlohmann::ordered_json::parse(
      R"({"cmd":"run","current":12,"latest":99,"decided":99,"paused":null,"matched":{"watch":"one","t":12,"detected":12,"group":{"a":12},"matches":1}})");
  EXPECT_EQ(answer_words(matched), "stopped at step 12 on a match of one: a=12");
  const auto action =
      nlohmann::ordered_json::parse(R"({"cmd":"action","watch":"two_leaders","was":"pause","action":"log"})");
  EXPECT_EQ(answer_words(action), "two_leaders logs its matches from now on (it paused on them before)");
  // A push that moves nothing says why after what was done.
  const auto pushed = nlohmann::ordered_json::parse(
      R"({"cmd":"push","intervention":{"at":2,"module":0,"push":[0.0,0.0,5.0]},"dropped_steps":0,"current":1,"latest":1,"decided":1,"warning":"module 0 is latched to the ground at step 1"})");
  EXPECT_EQ(answer_words(pushed),
            "intervention at step 2; at step 1 (0 to 1 simulated); but module 0 is latched to the ground at step 1");
  for (const auto* a : {&paused, &seek, &save, &matched, &action, &pushed})
    EXPECT_EQ(answer_words(*a).find('{'), std::string::npos);
}

}  // namespace
}  // namespace dw::view
