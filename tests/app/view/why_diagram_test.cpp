// The Why panel's diagram (app/view/why_diagram.h) read from the session's own `why` answers, without
// a window: on the leader election paused on two leaders, the narrow cone of isLeader of 7 at step 1
// is 7's column first and its four one-hop neighbours' (the 1-hop bug), one dot per event and one
// arrow per message where the answer puts them; a match's cone puts its group's columns first; every
// cause across columns is drawn, as a message or as a link through dropped events; and the view
// fits, zooms about the mouse and stays within the diagram.
#include <gtest/gtest.h>

#include <set>

#include "app/view/why_diagram.h"
#include "scenarios/scenario.h"
#include "shell/options.h"
#include "shell/shell.h"

namespace dw::view {
namespace {

class WhyDiagramTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto loaded = scenarios::load_scenario(std::string(DWATCH_SCENARIOS_DIR) + "/leader_election.toml");
    ASSERT_TRUE(std::holds_alternative<scenarios::Scenario>(loaded)) << std::get<std::string>(loaded);
    scenario_ = std::make_unique<scenarios::Scenario>(std::get<scenarios::Scenario>(std::move(loaded)));
    session_ =
        std::make_unique<sim::Session>(*scenario_->model, *scenario_->world, shell::session_options(*scenario_, {}));
    shell_ = std::make_unique<shell::Shell>(*scenario_, *session_);
    ASSERT_EQ(ask("run")["paused"]["t"], 1);
  }
  nlohmann::ordered_json ask(const std::string& line) {
    const watch::SourceText source("<test>", line);
    auto parsed = shell_->parse(source, 0, 1);
    EXPECT_TRUE(std::holds_alternative<std::optional<shell::Command>>(parsed)) << line;
    auto answer = shell_->execute(*std::get<std::optional<shell::Command>>(parsed));
    EXPECT_TRUE(std::holds_alternative<nlohmann::ordered_json>(answer)) << std::get<std::string>(answer);
    return std::get<nlohmann::ordered_json>(answer);
  }

  std::unique_ptr<scenarios::Scenario> scenario_;
  std::unique_ptr<sim::Session> session_;
  std::unique_ptr<shell::Shell> shell_;
};

TEST_F(WhyDiagramTest, TheNarrowConeOfALeaderIsItsColumnAndItsOneHopNeighboursMessages) {
  const std::string line = "why 7 isLeader 1 --narrow";
  const auto answer = ask(line);
  const auto d = why_diagram(answer, line);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->command, line);
  EXPECT_EQ(d->title, "isLeader of 7 = 1 at step 1: set at step 1 by its program");
  EXPECT_EQ(d->modules, (std::vector<uint32_t>{7, 6, 8, 18, 19}));  // the value's module first
  EXPECT_EQ(d->group_column, (std::vector<bool>{true, false, false, false, false}));
  EXPECT_EQ(d->first, 0);
  EXPECT_EQ(d->last, 1);
  ASSERT_EQ(d->dots.size(), answer["events"].size());
  for (size_t i = 0; i < d->dots.size(); ++i) {
    const WhyDot& dot = d->dots[i];
    EXPECT_EQ(dot.module, answer["events"][i]["module"].get<uint32_t>());
    EXPECT_EQ(d->modules[size_t(dot.column)], dot.module);
    EXPECT_EQ(dot.step, answer["events"][i]["step"].get<int64_t>());
    EXPECT_TRUE(dot.changed);
  }
  const WhyDot& origin = d->dots.back();
  EXPECT_TRUE(origin.origin);
  EXPECT_EQ(origin.column, 0);
  EXPECT_NE(origin.text.find("isLeader  0 -> 1"), std::string::npos) << origin.text;
  // One arrow per message, each into 7's column from a neighbour's, sent at 0 and read at 1; no
  // other link (every cause is a message or 7's own column).
  ASSERT_EQ(d->arrows.size(), answer["messages"].size());
  for (const WhyArrow& a : d->arrows) {
    EXPECT_TRUE(a.message);
    EXPECT_EQ(a.to_column, 0);
    EXPECT_NE(a.from_column, 0);
    EXPECT_EQ(a.sent, 0);
    EXPECT_EQ(a.read, 1);
    EXPECT_NE(a.text.find("words [0, "), std::string::npos) << a.text;
  }
}

TEST_F(WhyDiagramTest, AMatchsGroupComesFirstAndEveryCauseAcrossColumnsIsDrawn) {
  const std::string line = "why match two_leaders 0";
  const auto answer = ask(line);
  const auto d = why_diagram(answer, line);
  ASSERT_TRUE(d);
  ASSERT_GE(d->modules.size(), 3u);
  EXPECT_EQ(std::vector<uint32_t>(d->modules.begin(), d->modules.begin() + 3), (std::vector<uint32_t>{7, 6, 17}));
  EXPECT_TRUE(d->group_column[0] && d->group_column[1] && d->group_column[2]);
  EXPECT_EQ(d->title.find("two_leaders matched at step 1 (a=7 b=6 c=17)"), 0u) << d->title;
  // Each cause from another module is an arrow into its event: a message or a link.
  std::set<std::tuple<int, int, int64_t, int64_t>> drawn;
  for (const WhyArrow& a : d->arrows) drawn.insert({a.from_column, a.to_column, a.sent, a.read});
  size_t across = 0;
  for (const WhyDot& dot : d->dots)
    for (const auto& c : answer["events"][dot.event]["causes"]) {
      const WhyDot& cause = d->dots[c.get<size_t>()];
      if (cause.column == dot.column) continue;
      ++across;
      EXPECT_TRUE(drawn.count({cause.column, dot.column, cause.step, dot.step}))
          << cause.module << "@" << cause.step << " -> " << dot.module << "@" << dot.step;
    }
  EXPECT_GT(across, 0u);
  // The full cone (not narrow) reaches back to step 0 and marks steady chatter as not new.
  EXPECT_EQ(d->first, 0);
  EXPECT_EQ(d->last, 1);
}

TEST(WhyView, FitsZoomsAboutTheMouseAndStaysWithinTheDiagram) {
  WhyDiagram d;
  d.modules = {1, 2, 3, 4};
  d.group_column = {true, false, false, false};
  d.first = 10;
  d.last = 13;
  WhyView v;
  v.fit(d, 400, 200);
  EXPECT_FLOAT_EQ(v.column_width, 100);  // within 44..110
  EXPECT_FLOAT_EQ(v.step_height, 50);
  EXPECT_FLOAT_EQ(v.x_of(0), 50);
  EXPECT_FLOAT_EQ(v.y_of(11, d.first), 75);
  // Zoomed in about step 11's row: it stays under the mouse.
  v.zoom(2, 75);
  EXPECT_FALSE(v.fitted);
  EXPECT_NEAR(v.y_of(11, d.first), 75, 1e-3);
  v.pan(0, 1000);  // dragged far down: clamped to the top
  v.clamp(d, 400, 200);
  EXPECT_FLOAT_EQ(v.scroll_y, 0);
  v.pan(-1000, -1000);
  v.clamp(d, 400, 200);
  EXPECT_FLOAT_EQ(v.scroll_y, 400 - 200);  // 4 steps of 100 in a frame of 200
  EXPECT_FLOAT_EQ(v.scroll_x, 0);          // 4 columns of 100 fit in 400
  v.fit(d, 100, 200);
  EXPECT_FLOAT_EQ(v.column_width, WhyView::kMinColumn);  // never narrower: the columns scroll
  v.pan(-1000, 0);
  v.clamp(d, 100, 200);
  EXPECT_FLOAT_EQ(v.scroll_x, 4 * WhyView::kMinColumn - 100);
  EXPECT_FLOAT_EQ(distance_to_segment(5, 5, 0, 0, 10, 0), 5);
  EXPECT_FLOAT_EQ(distance_to_segment(-3, 4, 0, 0, 10, 0), 5);
}

TEST(WhyDiagramOf, AnAnswerThatIsNotWhyIsNone) {
  EXPECT_FALSE(why_diagram({{"cmd", "seek"}, {"current", 3}}, "seek 3"));
}

}  // namespace
}  // namespace dw::view
