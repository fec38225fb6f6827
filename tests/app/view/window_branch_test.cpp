// The window after an intervention (issue 64's bug "trying a fix erases the match paused on"): the
// session decides the current step again on the new branch (sim/session_interventions.cpp), so the
// paused match's lane, its count and the position line stay as they were.
#include "tests/app/view/window_fixture.h"

namespace {

using namespace dw_window_test;

// Pixels of the first lane's colour (widgets.cpp, lane_color(0)) in the timeline's first lane.
int first_lane_pixels(const dw::render::Image& image, const json& timeline) {
  const int x0 = int(timeline["x0"].get<double>()), x1 = x0 + int(timeline["width"].get<double>());
  const int y0 = int(timeline["y0"].get<double>()) + 2, y1 = y0 + 14;
  int count = 0;
  for (int y = std::max(0, y0); y < std::min(image.height, y1); ++y)
    for (int x = std::max(0, x0); x < std::min(image.width, x1); ++x) {
      const uint8_t* p = image.pixel(x, y);
      if (std::abs(p[0] - 230) < 20 && std::abs(p[1] - 85) < 20 && std::abs(p[2] - 60) < 20) ++count;
    }
  return count;
}

// Paused on two leaders at step 1 (found at step 3, lag 2), Set on module 7 (from step 2 on) keeps
// the 91 matches of step 1, their lane and "decided through 1" (it said 0 matches, an empty lane
// and "decided through -1").
TEST_F(Window, SetAtThePausedStepKeepsItsMatches) {
  const Outcome view = dwatch("view " + kLeader,
                              "run\nclick 7\nscreenshot before.png\npanel timeline\npress Set\npanel watchpoints\n"
                              "panel position\nscreenshot after.png\npanel timeline\n",
                              true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 9u) << view.err;
  ASSERT_EQ(view.answers[0]["paused"]["matches"], 91);
  EXPECT_EQ(view.answers[4]["current"], 1);
  EXPECT_EQ(view.answers[5]["rows"][0]["name"], "two_leaders");
  EXPECT_EQ(view.answers[5]["rows"][0]["matches"], 91) << "the match paused on was erased";
  EXPECT_EQ(view.answers[6]["current"], 1);
  EXPECT_GE(view.answers[6]["decided"].get<int64_t>(), 1);
  std::string error;
  const auto before = dw::render::read_png((dir_ / "before.png").string(), &error);
  const auto after = dw::render::read_png((dir_ / "after.png").string(), &error);
  ASSERT_TRUE(before && after) << error;
  const int lit_before = first_lane_pixels(*before, view.answers[3]),
            lit_after = first_lane_pixels(*after, view.answers[8]);
  EXPECT_GT(lit_before, 20) << "the paused match's lane shows";
  EXPECT_GT(lit_after, lit_before / 2) << "its lane emptied after Set";
}

}  // namespace
