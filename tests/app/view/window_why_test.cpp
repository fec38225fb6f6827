// The Why panel on the pixels (issue 63): opened by the Module panel's "why?" beside isLeader on the
// leader election paused on two leaders, its diagram has a dot where the session's answer has an
// event and an arrow where it has a message (each checked on the screenshot); Y asks the same of the
// selected module's last changed variable; a click on a dot goes to its step and selects its module.
#include "tests/app/view/window_fixture.h"

namespace {

using namespace dw_window_test;

// The panel's colours (app/view/why_panel.cpp).
constexpr int kChanged[3] = {250, 200, 60}, kOrigin[3] = {255, 105, 50}, kMessage[3] = {110, 205, 255};

bool near(const uint8_t* p, const int (&c)[3]) {
  return std::abs(p[0] - c[0]) <= kTolerance && std::abs(p[1] - c[1]) <= kTolerance &&
         std::abs(p[2] - c[2]) <= kTolerance;
}
// Some pixel within `r` of (x, y) has colour c.
bool near_any(const dw::render::Image& image, double x, double y, int r, const int (&c)[3]) {
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx) {
      const int px = int(x) + dx, py = int(y) + dy;
      if (px >= 0 && py >= 0 && px < image.width && py < image.height && near(image.pixel(px, py), c)) return true;
    }
  return false;
}

TEST_F(Window, TheWhyPanelDrawsTheAnswersEventsAndMessagesAndAClickOnADotSeeks) {
  // The session's own answer, to hold the diagram against.
  const Outcome session = dwatch("session " + kLeader, "run\nwhy 7 isLeader 1 --narrow\n", false);
  ASSERT_EQ(session.exit_code, 0) << session.err;
  ASSERT_EQ(session.answers.size(), 2u);
  const json& answer = session.answers[1];

  const Outcome view = dwatch("view " + kLeader,
                              "run\npress why? isLeader\npanel why\nscreenshot w.png\nkey y\npanel why\n"
                              "press why dot 6 0\npanel position\npanel inspector\n",
                              true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 9u) << view.err;
  const json& drawn = view.answers[2];
  ASSERT_TRUE(drawn["open"].get<bool>()) << drawn.dump();
  EXPECT_EQ(drawn["command"], "why 7 isLeader 1 --narrow");
  EXPECT_EQ(drawn["title"], "isLeader of 7 = 1 at step 1: set at step 1 by its program");
  std::string error;
  const auto image = dw::render::read_png((dir_ / "w.png").string(), &error);
  ASSERT_TRUE(image) << error;
  const json& frame = drawn["frame"];
  auto in_frame = [&](double x, double y) {
    return x >= frame[0].get<double>() && x <= frame[2].get<double>() && y >= frame[1].get<double>() &&
           y <= frame[3].get<double>();
  };

  // A dot per event, where the answer puts it (module, step), in the event's colour.
  ASSERT_EQ(drawn["dots"].size(), answer["events"].size());
  for (size_t i = 0; i < drawn["dots"].size(); ++i) {
    const json& dot = drawn["dots"][i];
    const json& event = answer["events"][i];
    EXPECT_EQ(dot["module"], event["module"]);
    EXPECT_EQ(dot["step"], event["step"]);
    const double x = dot["centre"][0].get<double>(), y = dot["centre"][1].get<double>();
    ASSERT_TRUE(in_frame(x, y)) << dot.dump();
    EXPECT_TRUE(near(image->pixel(int(x), int(y)), event.value("origin", false) ? kOrigin : kChanged))
        << "no dot drawn at " << x << "," << y << " for " << event.dump();
  }
  // The dots of one step on one row, the steps downward, one column per module.
  const json& origin = drawn["dots"][answer["events"].size() - 1];
  EXPECT_GT(origin["centre"][1].get<double>(), drawn["dots"][0]["centre"][1].get<double>() + 20);
  // An arrow per message, from (sender, step sent) to (receiver, step read): its middle on the pixels.
  ASSERT_EQ(drawn["arrows"].size(), answer["messages"].size());
  for (size_t i = 0; i < drawn["arrows"].size(); ++i) {
    const json& a = drawn["arrows"][i];
    const json& m = answer["messages"][i];
    EXPECT_EQ(a["from"], m["from"]);
    EXPECT_EQ(a["to"], m["to"]);
    EXPECT_EQ(a["sent"], m["sent"]);
    EXPECT_EQ(a["read"], m["read"]);
    const json& l = a["line"];
    // Its ends are the dots of the sender's event and the receiver's.
    bool from_dot = false, to_dot = false;
    for (const json& dot : drawn["dots"]) {
      from_dot |= dot["module"] == m["from"] && dot["step"] == m["sent"] && dot["centre"][0] == l[0] &&
                  dot["centre"][1] == l[1];
      to_dot |=
          dot["module"] == m["to"] && dot["step"] == m["read"] && dot["centre"][0] == l[2] && dot["centre"][1] == l[3];
    }
    EXPECT_TRUE(from_dot && to_dot) << a.dump();
    const double mx = (l[0].get<double>() + l[2].get<double>()) / 2, my = (l[1].get<double>() + l[3].get<double>()) / 2;
    EXPECT_TRUE(near_any(*image, mx, my, 1, kMessage)) << "no arrow drawn through " << mx << "," << my;
  }
  // Nothing drawn where the answer has nothing: module 6's column at step 1 (no event, no message).
  const json* six = nullptr;
  for (const json& dot : drawn["dots"])
    if (dot["module"] == 6) six = &dot;
  ASSERT_TRUE(six);
  const double empty_y = origin["centre"][1].get<double>(), empty_x = (*six)["centre"][0].get<double>();
  EXPECT_FALSE(near_any(*image, empty_x, empty_y, 3, kChanged) || near_any(*image, empty_x, empty_y, 3, kMessage));

  // Y: the selected module's (7's) last changed variable, isLeader at this step.
  EXPECT_EQ(view.answers[5]["command"], "why 7 isLeader 1 --narrow");
  // A click on module 6's dot at step 0: the cursor goes there and 6 is selected.
  EXPECT_EQ(view.answers[6]["current"], 0);
  EXPECT_EQ(view.answers[7]["current"], 0);
  EXPECT_EQ(view.answers[8]["module"], 6);
}

}  // namespace
