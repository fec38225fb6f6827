// The Group tab and the reverse search (issue 64): the paused match's group side by side with its
// whole values, a pinned condition decided as the session's `eval` decides it, and the buttons that
// go back and on to where a condition holds or a variable changed landing where the session's
// `find` lands; the table seen whole on the screenshot's pixels.
#include "tests/app/view/window_fixture.h"

namespace {

using namespace dw_window_test;

const std::string kPin = "a._priority > c._priority";
const std::string kGroup = "7 6 17";

TEST_F(Window, TheGroupTabShowsTheMatchSideBySideAndItsPinsAsTheSessionDecidesThem) {
  const Outcome view = dwatch("view " + kLeader,
                              "run\n"              // 0: pauses at step 1, a=7 b=6 c=17
                              "press tab group\n"  // 1
                              "type condition " +
                                  kPin +
                                  "\n"                      // 2
                                  "press pin\n"             // 3
                                  "wait 3\n"                // 4
                                  "panel group\n"           // 5
                                  "screenshot group.png\n"  // 6
                                  "panel widgets\n"         // 7
                                  "state 7\n"               // 8
                                  "state 17\n"              // 9
                                  "eval " +
                                  kGroup + " modules(a b c); " + kPin +
                                  "\n"                              // 10
                                  "type condition b.nothere = 1\n"  // 11
                                  "press pin\n"                     // 12
                                  "panel group\n",                  // 13
                              true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 14u) << view.err;
  const json& group = view.answers[5];
  ASSERT_EQ(group["group"], json({{"a", 7}, {"b", 6}, {"c", 17}})) << group;
  // Whole values, as `state` answers them.
  EXPECT_EQ(group["vars"]["_priority"][0]["value"], view.answers[8]["vars"]["_priority"]);
  EXPECT_EQ(group["vars"]["_priority"][2]["value"], view.answers[9]["vars"]["_priority"]);
  EXPECT_EQ(group["vars"]["isLeader"][0]["value"], 1);
  EXPECT_EQ(group["vars"]["isLeader"][0]["changed"], true) << "a became leader at step 1";
  ASSERT_EQ(group["pins"].size(), 1u);
  EXPECT_EQ(group["pins"][0]["text"], kPin);
  ASSERT_TRUE(group["pins"][0]["value"].is_boolean()) << group;
  EXPECT_EQ(group["pins"][0]["value"], view.answers[10]["value"]) << "the pin and `eval` disagree";
  // A pin naming no variable is refused where it was typed, and not pinned.
  EXPECT_EQ(view.answers[13]["pins"].size(), 1u);
  // Seen whole: each slot's header and the table's values on the screenshot.
  const json& widgets = view.answers[7]["widgets"];
  std::vector<json> headers;
  for (const json& w : widgets)
    if (w["name"].get<std::string>().rfind("group: ", 0) == 0) headers.push_back(w);
  ASSERT_EQ(headers.size(), 4u) << "variable, a=7, b=6, c=17";
  std::string error;
  const auto shot = dw::render::read_png((dir_ / "group.png").string(), &error);
  ASSERT_TRUE(shot) << error;
  for (const json& h : headers) {
    EXPECT_FALSE(h["cut"].get<bool>()) << h;
    EXPECT_FALSE(h["out_of_sight"].get<bool>()) << h;
    // Text under the header: light pixels in the rows below it.
    const int x0 = int(h["rect"][0].get<double>()), x1 = int(h["rect"][2].get<double>());
    const int y0 = int(h["rect"][3].get<double>()), y1 = y0 + 70;
    int light = 0;
    for (int y = y0; y < y1 && y < shot->height; ++y)
      for (int x = x0; x < x1 && x < shot->width; ++x)
        light += shot->pixel(x, y)[0] > 200 && shot->pixel(x, y)[1] > 200;
    EXPECT_GT(light, 30) << h["name"] << ": no values drawn under it";
  }
}

// "<" and ">" land where the session's `find` lands: a pin's, over the group, and a variable's
// change, from the Module panel.
TEST_F(Window, ThePinsAndVariablesSearchBackAndOnAsFindDoes) {
  const std::string cond = "times[30](a.isLeader = 1) >= 25";  // first at step 25
  const Outcome view = dwatch("view " + kLeader,
                              "action two_leaders log\n"  // 0
                              "run 40\n"                  // 1
                              "seek 1\n"                  // 2
                              "find next " +
                                  kGroup + " when modules(a b c); " + cond +
                                  "\n"                 // 3
                                  "click match 0\n"    // 4: step 1, a=7 b=6 c=17
                                  "press tab group\n"  // 5
                                  "type condition " +
                                  cond +
                                  "\n"                      // 6
                                  "press pin\n"             // 7
                                  "press > holds 0\n"       // 8
                                  "seek 3\n"                // 9
                                  "find prev 7 isLeader\n"  // 10
                                  "seek 3\n"                // 11
                                  "click 7\n"               // 12
                                  "press < change\n",       // 13
                              true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 14u) << view.err;
  ASSERT_TRUE(view.answers[3]["found"].is_number()) << view.answers[3];
  EXPECT_EQ(view.answers[8]["current"], view.answers[3]["found"]) << view.answers[8];
  ASSERT_TRUE(view.answers[10]["found"].is_number()) << view.answers[10];
  EXPECT_EQ(view.answers[13]["current"], view.answers[10]["found"]) << view.answers[13];
}

// A bookmark made in the marks tab is a yellow flag on the timeline at its step and is saved with
// the scenario; the diff tab lists what differs between step 0 and the current one, as `diff`
// answers, and rings those modules in the 3D view.
TEST_F(Window, BookmarksFlagTheTimelineAndADiffRingsItsModules) {
  const Outcome view = dwatch("view " + kLeader,
                              "run\n"                    // 0: step 1
                              "press tab marks\n"        // 1
                              "type note two leaders\n"  // 2
                              "press mark this step\n"   // 3
                              "marks\n"                  // 4
                              "panel timeline\n"         // 5
                              "screenshot marks.png\n"   // 6
                              "save saved.toml\n"        // 7
                              "diff 0 1\n"               // 8
                              "press tab diff\n"         // 9
                              "type diff-step 0\n"       // 10
                              "press diff\n"             // 11
                              "click 7\n"                // 12
                              "screenshot diff.png\n",   // 13
                              true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 14u) << view.err;
  EXPECT_EQ(view.answers[4]["marks"], json::parse(R"([{"at":1,"note":"two leaders"}])"));
  EXPECT_NE(slurp(dir_ / "saved.toml").find("[[bookmark]]\nat = 1\nnote = \"two leaders\""), std::string::npos)
      << slurp(dir_ / "saved.toml");
  // The flag: yellow pixels at step 1's x, at the top of the lanes.
  const json& tl = view.answers[5];
  const double x = tl["x0"].get<double>() + (1.5 - tl["first"].get<double>()) * tl["width"].get<double>() /
                                                (tl["last"].get<double>() - tl["first"].get<double>() + 1);
  std::string error;
  const auto marks = dw::render::read_png((dir_ / "marks.png").string(), &error);
  ASSERT_TRUE(marks) << error;
  int yellow = 0;
  for (int py = int(tl["y0"].get<double>()); py < int(tl["y0"].get<double>()) + 10; ++py)
    for (int px = int(x) - 8; px <= int(x) + 8; ++px) {
      const uint8_t* p = marks->pixel(px, py);
      yellow += p[0] > 200 && p[1] > 180 && p[2] < 120;
    }
  EXPECT_GT(yellow, 15) << "no bookmark flag at step 1";
  // The diff: as the session answers it, and module 7 (its isLeader changed) ringed in cyan.
  ASSERT_GT(view.answers[8]["count"].get<int>(), 0);
  EXPECT_NE(view.answers[11]["status"].get<std::string>().find(view.answers[8]["count"].dump() + " modules differ"),
            std::string::npos)
      << view.answers[11];
  bool seven = false;
  for (const json& row : view.answers[8]["modules"]) seven = seven || row["module"] == 7;
  ASSERT_TRUE(seven) << view.answers[8];
  const auto diff = dw::render::read_png((dir_ / "diff.png").string(), &error);
  ASSERT_TRUE(diff) << error;
  const int cx = int(view.answers[12]["pixel"][0].get<double>()), cy = int(view.answers[12]["pixel"][1].get<double>());
  int cyan = 0;  // the ring is about the body's centre, below the top face a click reports
  for (int py = cy - 20; py < cy + 80; ++py)
    for (int px = cx - 40; px < cx + 40; ++px) {
      const uint8_t* p = diff->pixel(px, py);
      cyan += p[0] < 140 && p[1] > 190 && p[2] > 200;
    }
  EXPECT_GT(cyan, 20) << "module 7 is not ringed";
}

}  // namespace
