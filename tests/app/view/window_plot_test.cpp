// The Module panel's history plot on the pixels (issue 64): 19-digit values apart to the pixel
// and written whole on its axis, the whole history drawn (a one-step spike among 1000 steps still
// shows), its steps' line in sight under it at the default size, and a match's group drawn together.
#include "tests/app/view/window_fixture.h"

namespace {

using namespace dw_window_test;

// The plot line's pixels (the window's kPlotLineColor) in columns x0..x1 of a plot area: how many
// in the top fifth of its height, in the bottom fifth, and in all.
struct Bands {
  int top = 0, bottom = 0, all = 0;
};
Bands line_bands(const dw::render::Image& image, const json& rect, int x0, int x1) {
  const int y0 = int(rect[1].get<double>()), y1 = int(rect[3].get<double>());
  Bands b;
  for (int y = y0; y < y1 && y < image.height; ++y)
    for (int x = x0; x < x1 && x < image.width; ++x) {
      const uint8_t* p = image.pixel(x, y);
      if (std::abs(p[0] - 130) >= 25 || std::abs(p[1] - 200) >= 25 || p[2] <= 220) continue;
      ++b.all;
      if (y < y0 + (y1 - y0) / 5) ++b.top;
      if (y > y1 - (y1 - y0) / 5) ++b.bottom;
    }
  return b;
}

const json* label_of(const json& plots, const std::string& text) {
  for (const json& l : plots["plot_labels"])
    if (l["text"] == text) return &l;
  return nullptr;
}

class Plot : public Window {
 protected:
  // A line of 3 modules whose one variable v is `value` (Lua, of m.step) over `steps` steps: run,
  // module 1 selected, the plots' places answered and the window shot as p.png.
  Outcome plot_of(const std::string& value, int steps) {
    std::ofstream(dir_ / "x.lua") << "program = { vars = { \"v\" } }\nfunction step(m) m:set(\"v\", " << value
                                  << ") end\n";
    std::ofstream(dir_ / "s.toml") << "steps = " << steps
                                   << "\n[lattice]\nkind = \"line\"\nsize = [3]\n[[program]]\nscript = \"x.lua\"\n";
    return dwatch("view s.toml", "run\nclick 1\nwait 3\npanel plots\nscreenshot p.png\n", true);
  }
  std::optional<dw::render::Image> shot() {
    std::string error;
    auto image = dw::render::read_png((dir_ / "p.png").string(), &error);
    EXPECT_TRUE(image) << error;
    return image;
  }
};

// 19-digit values one apart (as floats they were one value: a constant across the middle, its axis
// "9.20345e+18"): step 0 at the bottom, step 1 at the top, and both values written whole, their
// labels' pixels apart.
TEST_F(Plot, NineteenDigitValuesOneApartAreDrawnApartAndWrittenWhole) {
  const Outcome view = plot_of("9203446857844391000 + m.step % 2", 12);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 5u) << view.err;
  const json& plots = view.answers[3];
  ASSERT_EQ(plots["plot_rects"].size(), 1u) << "the Module plot (no watchpoint: no statistics)";
  const json& rect = plots["plot_rects"][0];
  const auto image = shot();
  ASSERT_TRUE(image);
  // 12 steps across the area: step 0's and step 1's columns, a few pixels in from their edges.
  const double x0 = rect[0].get<double>(), step = (rect[2].get<double>() - x0) / 12;
  const Bands even = line_bands(*image, rect, int(x0 + 3), int(x0 + step - 3));
  const Bands odd = line_bands(*image, rect, int(x0 + step + 3), int(x0 + 2 * step - 3));
  EXPECT_GT(even.all, 0);
  EXPECT_EQ(even.bottom, even.all) << "step 0 (the smaller) is not along the bottom";
  EXPECT_GT(odd.all, 0);
  EXPECT_EQ(odd.top, odd.all) << "step 1 (one more) is not along the top";
  const json* hi = label_of(plots, "9203446857844391001");
  const json* lo = label_of(plots, "9203446857844391000");
  ASSERT_TRUE(hi && lo) << plots.dump();
  // The two labels differ on the pixels (the same text "9.20345e+18" twice did not).
  int differ = 0;
  const int hx = int((*hi)["rect"][0].get<double>()), hy = int((*hi)["rect"][1].get<double>());
  const int lx = int((*lo)["rect"][0].get<double>()), ly = int((*lo)["rect"][1].get<double>());
  const int w = int((*hi)["rect"][2].get<double>()) - hx, h = int((*hi)["rect"][3].get<double>()) - hy;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      differ += std::abs(image->pixel(hx + x, hy + y)[0] - image->pixel(lx + x, ly + y)[0]) > 60;
  EXPECT_GT(differ, 5);
}

// The whole history (it was the last 100 steps), more steps than pixel columns: a one-step spike
// at step 625 of 1000 shows in its column at the top, and the axis spans steps 0 to 999.
TEST_F(Plot, TheWholeHistoryIsDrawnAndAOneStepSpikeShows) {
  const Outcome view = plot_of("(m.step == 625) and 1 or 0", 1000);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 5u) << view.err;
  const json& plots = view.answers[3];
  EXPECT_TRUE(label_of(plots, "step 0")) << plots.dump();
  EXPECT_TRUE(label_of(plots, "999")) << plots.dump();
  const json& rect = plots["plot_rects"][0];
  const auto image = shot();
  ASSERT_TRUE(image);
  const double x0 = rect[0].get<double>(), x1 = rect[2].get<double>();
  ASSERT_LT(x1 - x0, 1000) << "fewer columns than steps, or nothing is decimated";
  const int spike = int(x0 + (x1 - x0) * 625.5 / 1000);
  EXPECT_GT(line_bands(*image, rect, spike - 2, spike + 3).top, 0) << "the spike at step 625 does not show";
  EXPECT_EQ(line_bands(*image, rect, int(x0) + 2, spike - 4).top, 0);
  EXPECT_GT(line_bands(*image, rect, int(x0) + 2, spike - 4).bottom, 0);
}

// At the default size the plot's steps' line is whole under it ("step 0" was cut in half by the
// Module panel's edge): its lower half has the text's grey pixels. So it is with the group tab
// open, which takes more of the column (the Module panel gave it room, and its plot was squeezed
// to 40 pixels with its steps cut).
TEST_F(Window, ThePlotsStepsAreInSightUnderIt) {
  for (const std::string tab : {"", "press tab group\n"}) {
    const Outcome view =
        dwatch("view " + kLeader, "run\n" + tab + "click 7\nwait 3\npanel plots\nscreenshot p.png\n", true);
    ASSERT_EQ(view.exit_code, 0) << view.err;
    const size_t plots = tab.empty() ? 3 : 4;
    ASSERT_EQ(view.answers.size(), plots + 2) << view.err;
    const json& area = view.answers[plots]["plot_rects"][0];
    EXPECT_GE(area[3].get<double>() - area[1].get<double>(), 35) << "the plot squeezed, after: " << tab;
    const json* first = label_of(view.answers[plots], "step 0");
    ASSERT_TRUE(first) << view.answers[plots].dump();
    std::string error;
    const auto image = dw::render::read_png((dir_ / "p.png").string(), &error);
    ASSERT_TRUE(image) << error;
    const json& r = (*first)["rect"];
    const int x0 = int(r[0].get<double>()), x1 = int(r[2].get<double>());
    const int y0 = int(r[1].get<double>()), y1 = int(r[3].get<double>());
    int grey = 0;
    for (int y = (y0 + y1) / 2; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const uint8_t* p = image->pixel(x, y);
        if (p[0] > 70 && p[0] < 180 && std::abs(p[0] - p[1]) < 12 && std::abs(p[1] - p[2]) < 12) ++grey;
      }
    EXPECT_GT(grey, 10) << "the lower half of 'step 0' is hidden" << (tab.empty() ? "" : ", the group tab open");
  }
}

// With a match selected, the Module plot draws the group's modules over the same axes, each in its
// colour and named after the title: at step 1 of leader_election a=7 and c=17 became leaders and
// b=6 did not, so b's orange line lies along the bottom after step 1 while a's blue and c's green
// ones are at the top; each name is written in its line's colour.
TEST_F(Window, TheModulePlotDrawsTheSelectedMatchsGroupTogether) {
  const Outcome view = dwatch("view " + kLeader,
                              "run\nrun 40\nseek 1\npress plot isLeader\nwait 3\npanel inspector\npanel plots\n"
                              "screenshot p.png\n",
                              true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 8u) << view.err;
  EXPECT_EQ(view.answers[5]["plot"]["lines"], json({"a=7", "b=6", "c=17"})) << view.answers[5];
  const json& plots = view.answers[6];
  std::string error;
  const auto image = dw::render::read_png((dir_ / "p.png").string(), &error);
  ASSERT_TRUE(image) << error;
  const json& rect = plots["plot_rects"][0];
  const int x0 = int(rect[0].get<double>()), x1 = int(rect[2].get<double>());
  const int y0 = int(rect[1].get<double>()), y1 = int(rect[3].get<double>());
  // Pixels of a colour in the plot's top and bottom fifths, right of step 1's start (of 41 steps).
  auto count = [&](std::array<int, 3> rgb, bool top) {
    int n = 0;
    const int from = x0 + (x1 - x0) * 3 / 41;
    for (int y = top ? y0 : y1 - (y1 - y0) / 5; y < (top ? y0 + (y1 - y0) / 5 : y1); ++y)
      for (int x = from; x < x1; ++x) {
        const uint8_t* p = image->pixel(x, y);
        n += std::abs(p[0] - rgb[0]) < 25 && std::abs(p[1] - rgb[1]) < 25 && std::abs(p[2] - rgb[2]) < 25;
      }
    return n;
  };
  const std::array<int, 3> blue{130, 200, 250}, orange{250, 150, 60}, green{120, 220, 110};
  EXPECT_GT(count(blue, true), 50) << "a's line is not at the top";
  EXPECT_GT(count(green, true), 50) << "c's line is not at the top, beside a's";
  EXPECT_GT(count(orange, false), 50) << "b's line is not along the bottom";
  EXPECT_EQ(count(orange, true), 0) << "b never led";
  // Each name in its line's colour.
  for (const auto& [name, rgb] : {std::pair{"b=6", orange}, std::pair{"c=17", green}}) {
    const json* l = label_of(plots, name);
    ASSERT_TRUE(l) << plots.dump();
    int coloured = 0;
    for (int y = int((*l)["rect"][1].get<double>()); y < int((*l)["rect"][3].get<double>()); ++y)
      for (int x = int((*l)["rect"][0].get<double>()); x < int((*l)["rect"][2].get<double>()); ++x) {
        const uint8_t* p = image->pixel(x, y);
        coloured += std::abs(p[0] - rgb[0]) < 40 && std::abs(p[1] - rgb[1]) < 40 && std::abs(p[2] - rgb[2]) < 40;
      }
    EXPECT_GT(coloured, 5) << name;
  }
}

}  // namespace
