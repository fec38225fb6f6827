// The 3D view at the scale users debug (issue 64, defect 12): a module that left the view has a
// pointer at the view's edge, and the camera follows a module (`T`, the script's `follow M`).
#include "tests/app/view/window_fixture.h"

namespace {

using namespace dw_window_test;

const std::string kPushWall = std::string(DWATCH_SCENARIOS_DIR) + "/push_wall.toml";

// The pointer's dark id plate: pixels near (x, y) darker than the light ground and modules.
int dark_pixels(const dw::render::Image& image, int cx, int cy, int reach) {
  int count = 0;
  for (int y = std::max(0, cy - reach); y < std::min(image.height, cy + reach); ++y)
    for (int x = std::max(0, cx - reach); x < std::min(image.width, cx + reach); ++x) {
      const uint8_t* p = image.pixel(x, y);
      if (p[0] < 50 && p[1] < 50 && p[2] < 60) ++count;
    }
  return count;
}

// push_wall at step 200: the ball tore modules off the wall and two lie outside the fitted view.
// Each has a pointer at the view's edge, on the screenshot (its dark id plate by the tip); followed,
// module 19 stands at the view's centre and needs no pointer.
TEST_F(Window, ModulesOutOfTheViewArePointedAtAndOneIsFollowed) {
  const Outcome view = dwatch("view " + kPushWall,
                              "run 200\nscreenshot wall.png\npanel pointers\nfollow 19\nscreenshot followed.png\n"
                              "panel pointers\nclick 19\n",
                              true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 7u) << view.err;
  const json& in_view = view.answers[1]["in_view"];
  const int out = in_view["of"].get<int>() - in_view["modules"].get<int>();
  ASSERT_GT(out, 0) << "the scene has no module out of the view to point at";
  const json& pointers = view.answers[2]["pointers"];
  int pointed = 0;
  bool nineteen = false;
  for (const json& p : pointers) pointed += 1 + p["more"].get<int>(), nineteen |= p["module"] == 19;
  EXPECT_EQ(pointed, out) << "every module out of the view is pointed at";
  ASSERT_TRUE(nineteen) << pointers.dump();
  const json& view_rect = view.answers[1]["view"];
  std::string error;
  const auto wall = dw::render::read_png((dir_ / "wall.png").string(), &error);
  ASSERT_TRUE(wall) << error;
  for (const json& p : pointers) {
    const float x = p["x"].get<float>(), y = p["y"].get<float>();
    EXPECT_TRUE(x >= view_rect["x"].get<float>() &&
                x <= view_rect["x"].get<float>() + view_rect["width"].get<float>() &&
                y >= view_rect["y"].get<float>() && y <= view_rect["y"].get<float>() + view_rect["height"].get<float>())
        << "the pointer lies in the view: " << p.dump();
    EXPECT_GT(dark_pixels(*wall, int(x), int(y), 45), 60) << "no pointer drawn at " << p.dump();
  }

  EXPECT_EQ(view.answers[3]["following"], 19);
  for (const json& p : view.answers[5]["pointers"]) EXPECT_NE(p["module"], 19) << "followed, it shows";
  const json& click = view.answers[6]["pixel"];
  // Near the centre of the ensemble's part of the view (below the title, right of the legend).
  EXPECT_NEAR(click[0].get<double>(), view_rect["width"].get<double>() / 2, view_rect["width"].get<double>() * 0.1);
  EXPECT_NEAR(click[1].get<double>(), view_rect["height"].get<double>() / 2, view_rect["height"].get<double>() * 0.1);
  EXPECT_EQ(view.answers[6]["selected"], 19);
}

// The colour-by menu is reached from a script as a person reaches it (issue 64's bug: it could
// not be): `press colour by` opens it, `press colour by: V` chooses, and the view is coloured so.
TEST_F(Window, AScriptChoosesWhatColoursTheModules) {
  const Outcome view = dwatch("view " + kLeader, "press colour by\npress colour by: _status\nscreenshot c.png\n", true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 3u) << view.err;
  EXPECT_EQ(view.answers[2]["color_by"], "_status");
}

// The Matches panel's watchpoint filter and the editor's "what it means" are reached from a script
// (they could not be): push_wall's torn_off chosen from the menu, the explanation opened.
TEST_F(Window, AScriptFiltersTheMatchesAndOpensWhatItMeans) {
  const Outcome view = dwatch("view " + kPushWall,
                              "run 100\npanel matches\npress match filter\npress match filter: torn_off\n"
                              "press edit torn_off\npress what it means\npanel matches\n",
                              true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 7u) << view.err;
  const int64_t total = view.answers[6]["total"].get<int64_t>();
  EXPECT_GT(total, 0);
  EXPECT_LT(total, view.answers[1]["total"].get<int64_t>()) << "not filtered";
  for (const json& row : view.answers[6]["rows"]) EXPECT_EQ(row["watch"], "torn_off") << row.dump();
}

// How much of the screenshot around (x, y) changed between two shots: pixels whose colour moved
// by more than the golden images' tolerance, within `reach`.
int changed_around(const dw::render::Image& a, const dw::render::Image& b, const json& pixel, int reach) {
  const int cx = int(pixel[0].get<double>()), cy = int(pixel[1].get<double>());
  int changed = 0;
  for (int y = std::max(0, cy - reach); y < std::min(a.height, cy + reach); ++y)
    for (int x = std::max(0, cx - reach); x < std::min(a.width, cx + reach); ++x)
      for (int c = 0; c < 3; ++c)
        if (std::abs(int(a.pixel(x, y)[c]) - int(b.pixel(x, y)[c])) > kTolerance) {
          ++changed;
          break;
        }
  return changed;
}

// Seeing inside: a cut across x leaves out the modules beyond the ensemble's middle (module 11, at
// the first row's far end, is gone; module 0, at its near end, stays), and Isolate (I) leaves out
// every module but the group's and the selection (module 12 is gone, the group's a stays).
TEST_F(Window, ACutPlaneAndIsolateLeaveModulesOut) {
  const Outcome view = dwatch("view " + kLeader,
                              "run\n"                    // 0: paused, a=7 b=6 c=17
                              "click 11\n"               // 1: where 11 shows
                              "click 12\n"               // 2
                              "click 0\n"                // 3: the selection, far from both
                              "screenshot all.png\n"     // 4
                              "press cut\n"              // 5
                              "press cut: cut x\n"       // 6
                              "screenshot cut.png\n"     // 7
                              "press cut\n"              // 8
                              "press cut: no cut\n"      // 9
                              "key i\n"                  // 10
                              "screenshot alone.png\n"   // 11
                              "key i\n"                  // 12
                              "screenshot again.png\n",  // 13
                              true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 14u) << view.err;
  std::string error;
  const auto all = dw::render::read_png((dir_ / "all.png").string(), &error);
  const auto cut = dw::render::read_png((dir_ / "cut.png").string(), &error);
  const auto alone = dw::render::read_png((dir_ / "alone.png").string(), &error);
  const auto again = dw::render::read_png((dir_ / "again.png").string(), &error);
  ASSERT_TRUE(all && cut && alone && again) << error;
  const json &p11 = view.answers[1]["pixel"], &p12 = view.answers[2]["pixel"], &p0 = view.answers[3]["pixel"];
  const json& a = view.answers[0]["paused"]["group"]["a"];
  ASSERT_EQ(a, 7);
  EXPECT_GT(changed_around(*all, *cut, p11, 8), 100) << "module 11 lies beyond the cut and still shows";
  EXPECT_LT(changed_around(*all, *cut, p0, 8), 30) << "module 0 lies on this side of the cut and changed";
  EXPECT_GT(changed_around(*all, *alone, p12, 8), 100) << "isolated, module 12 still shows";
  EXPECT_LT(changed_around(*all, *again, p12, 8), 30) << "I again did not bring module 12 back";
}

// Contacts (C) over the 3D view of a physical world: a 10^3 pile of free boxes at rest draws its
// contact points in magenta, none before C and none after C again; isolating the selected module
// (I) leaves only the contacts it takes part in, a few of the pile's.
TEST_F(Window, ContactsShowAndIsolateKeepsTheSelectionsOwn) {
  const std::string pile = std::string(DWATCH_SCENARIOS_DIR) + "/physics/pile.toml";
  const Outcome view = dwatch("view " + pile,
                              "run 30\nscreenshot off.png\nkey c\nscreenshot on.png\nclick 0\nkey i\n"
                              "screenshot isolated.png\nkey i\nkey c\nscreenshot off_again.png\n",
                              true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 10u) << view.err;
  const json& v = view.answers[1]["view"];
  auto magenta = [&](const std::string& name) {
    std::string error;
    const auto image = dw::render::read_png((dir_ / name).string(), &error);
    EXPECT_TRUE(image) << error;
    if (!image) return 0;
    int n = 0;
    for (int y = int(v["y"]); y < int(v["y"]) + int(v["height"]); ++y)
      for (int x = int(v["x"]); x < int(v["x"]) + int(v["width"]); ++x) {
        const uint8_t* p = image->pixel(x, y);
        n += p[0] > 200 && p[1] < 80 && p[2] > 180;
      }
    return n;
  };
  const int on = magenta("on.png"), isolated = magenta("isolated.png");
  EXPECT_EQ(magenta("off.png"), 0);
  EXPECT_GT(on, 20000) << "thousands of contacts in a resting pile";
  EXPECT_GT(isolated, 50) << "module 0's contacts: the ground and its three neighbours";
  EXPECT_LT(isolated, on / 20);
  EXPECT_EQ(magenta("off_again.png"), 0);
}

}  // namespace
