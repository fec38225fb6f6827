// The window at the scale users debug (issue 64), each defect seen on the pixels where it is
// visual: the selection shown through whatever covers it and apart from the group, Z zooming, the
// module plot telling the truth, values whole, the caret under its column, no flicker.
#include "tests/app/view/window_fixture.h"

namespace {

using namespace dw_window_test;

// Counts the selection ring's green pixels (the renderer's kSelectedOutline, shaded) within `reach`
// pixels of (cx, cy).
int green_pixels(const dw::render::Image& image, int cx, int cy, int reach) {
  int count = 0;
  for (int y = std::max(0, cy - reach); y < std::min(image.height, cy + reach); ++y)
    for (int x = std::max(0, cx - reach); x < std::min(image.width, cx + reach); ++x) {
      const uint8_t* p = image.pixel(x, y);
      if (p[1] > 150 && p[0] < 90 && p[2] < 110) ++count;
    }
  return count;
}

// The selection shows through whatever covers it and differs from the group's highlight: a module
// inside the flat lattice (its neighbours in front hid its rim) and a module of the paused group
// (it had the group's red rim, nothing else) both have a green ring around them.
TEST_F(Window, TheSelectionShowsThroughItsNeighboursAndDiffersFromTheGroup) {
  const Outcome view = dwatch(
      "view " + kLeader,
      "click 50\nscreenshot alone.png\nrun\nclick 7\nscreenshot group.png\nkey z\nclick 7\nscreenshot zoomed.png\n",
      true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 8u) << view.err;
  ASSERT_EQ(view.answers[3]["selected"], 7);
  ASSERT_EQ(view.answers[2]["paused"]["group"]["a"], 7) << "module 7 must lie in the group";
  for (const auto& [file, click] : {std::pair{"alone.png", 0}, std::pair{"group.png", 3}}) {
    std::string error;
    const auto shot = dw::render::read_png((dir_ / file).string(), &error);
    ASSERT_TRUE(shot) << error;
    const json& pixel = view.answers[size_t(click)]["pixel"];
    const int green = green_pixels(*shot, int(pixel[0].get<double>()), int(pixel[1].get<double>()), 60);
    EXPECT_GT(green, 300) << file << ": the selected module has no visible ring";
  }
  // Z zooms onto the selection and its group (it panned only): the ring grows with the module.
  std::string error;
  const auto group = dw::render::read_png((dir_ / "group.png").string(), &error);
  const auto zoomed = dw::render::read_png((dir_ / "zoomed.png").string(), &error);
  ASSERT_TRUE(group && zoomed) << error;
  const json& before = view.answers[3]["pixel"];
  const json& after = view.answers[6]["pixel"];
  const int near = green_pixels(*group, int(before[0].get<double>()), int(before[1].get<double>()), 60);
  const int close = green_pixels(*zoomed, int(after[0].get<double>()), int(after[1].get<double>()), 400);
  EXPECT_GT(close, 3 * near) << "Z did not zoom";
}

// The plot's line pixels (the window's kPlotLineColor) in a plot area: their rows' mean, as a
// share of the area's height from its top (0 top, 1 bottom); -1 when none is drawn.
double plot_line_height(const dw::render::Image& image, const json& rect, int x_from, int x_to) {
  const int y0 = int(rect[1].get<double>()), y1 = int(rect[3].get<double>());
  double sum = 0;
  int count = 0;
  for (int y = y0; y < y1 && y < image.height; ++y)
    for (int x = x_from; x < x_to && x < image.width; ++x) {
      const uint8_t* p = image.pixel(x, y);
      if (std::abs(p[0] - 130) < 25 && std::abs(p[1] - 200) < 25 && p[2] > 220) sum += y, ++count;
    }
  return count == 0 ? -1 : (sum / count - y0) / double(y1 - y0);
}

// The Module panel's plot tells the truth: a constant (module 20's _priority) is drawn across the
// middle, not along the bottom where it read as the smallest value; a 0/1 variable (its isLeader,
// 0 at step 0 and 1 at step 1) as a step from the bottom to the top, not a diagonal ramp. Module 20
// is a new leader outside the paused group: a group's modules share the plot's axes.
TEST_F(Window, TheModulePlotDrawsAConstantAsConstantAndAStepAsAStep) {
  const Outcome view = dwatch("view " + kLeader,
                              "run\nclick 20\nwait 3\npanel plots\nscreenshot step.png\npress plot _priority\nwait 3\n"
                              "panel plots\nscreenshot constant.png\n",
                              true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 9u) << view.err;
  ASSERT_EQ(view.answers[0]["current"], 1);
  std::string error;
  const auto step = dw::render::read_png((dir_ / "step.png").string(), &error);
  const auto constant = dw::render::read_png((dir_ / "constant.png").string(), &error);
  ASSERT_TRUE(step && constant) << error;
  const json& step_rect = view.answers[3]["plot_rects"][0];
  // The whole history: steps 0 to the last written under the plot's right end.
  const json& labels = view.answers[3]["plot_labels"];
  ASSERT_GE(labels.size(), 2u);
  const int steps = std::stoi(labels.back()["text"].get<std::string>()) + 1;
  const int x0 = int(step_rect[0].get<double>()), x1 = int(step_rect[2].get<double>());
  const int middle = x0 + (x1 - x0) / steps;
  // Step 0 (its column) at the bottom, step 1 at the top.
  EXPECT_GT(plot_line_height(*step, step_rect, x0 + 4, middle - 4), 0.85);
  const double right = plot_line_height(*step, step_rect, middle + 4, middle + (x1 - x0) / steps - 4);
  EXPECT_GE(right, 0);
  EXPECT_LT(right, 0.15);
  const json& constant_rect = view.answers[7]["plot_rects"][0];
  const double level = plot_line_height(*constant, constant_rect, int(constant_rect[0].get<double>()) + 4,
                                        int(constant_rect[2].get<double>()) - 4);
  EXPECT_GT(level, 0.35) << "a constant drawn along the bottom";
  EXPECT_LT(level, 0.65);
}

// The value that explains the bug shows whole: module 7's _priority (19 digits, cut to
// "9203446857844391..." at 1600 px) and the step before's, at the default size and at 1024x640.
TEST_F(Window, TheModulesValuesShowWhole) {
  for (const std::string size : {"", " --width 1024 --height 640"}) {
    const Outcome view = dwatch("view " + kLeader + size, "run\nclick 7\nwait 3\npanel widgets\n", true);
    ASSERT_EQ(view.exit_code, 0) << size << view.err;
    ASSERT_EQ(view.answers.size(), 4u) << view.err;
    EXPECT_EQ(view.answers[3]["cut_labels"], json::array()) << size;
    bool listed = false;
    for (const json& w : view.answers[3]["widgets"]) listed = listed || w["name"] == "plot _priority";
    EXPECT_TRUE(listed) << size << ": the variables' rows are not in the window";
  }
}

// The editor's caret points at the column the diagnostic names: typed with a mistake whose span
// starts at column 37, the caret line's '^' (the diagnostics' third red line) stands under the 37th character of the
// source line above it, measured in the screenshot's pixels (the source line's characters are
// as wide each as the line's width over its length, which only a monospace font makes true).
TEST_F(Window, TheEditorsCaretStandsUnderTheColumnItNames) {
  const std::string text = "modules(a b); (a.isLeader = 1) and (b.isLeadr = 1)";  // the span of b.isLeadr: column 37
  const Outcome view =
      dwatch("view " + kLeader, "type text " + text + "\nwait 2\npanel widgets\nscreenshot e.png\n", true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 4u) << view.err;
  json field;
  for (const json& w : view.answers[2]["widgets"])
    if (w["name"] == "text") field = w["rect"];
  ASSERT_FALSE(field.is_null());
  std::string error;
  const auto shot = dw::render::read_png((dir_ / "e.png").string(), &error);
  ASSERT_TRUE(shot) << error;
  // The diagnostics' red text rows under the field, grouped into lines; per line its red extent.
  const int x0 = int(field[0].get<double>()), x1 = int(field[2].get<double>()), top = int(field[3].get<double>());
  struct Line {
    int left = 1 << 30, right = -1;
  };
  std::vector<Line> lines;
  bool in_line = false;
  for (int y = top; y < std::min(shot->height, top + 200); ++y) {
    Line row;
    for (int x = x0; x < x1; ++x) {
      const uint8_t* p = shot->pixel(x, y);
      if (p[0] > 90 && p[0] > p[1] + 40 && p[0] > p[2] + 40) row.left = std::min(row.left, x), row.right = x;
    }
    if (row.right < 0) {
      in_line = false;
      continue;
    }
    if (!in_line) lines.push_back(row);
    lines.back().left = std::min(lines.back().left, row.left);
    lines.back().right = std::max(lines.back().right, row.right);
    in_line = true;
  }
  // The diagnostic's first line, its source line, then its caret line (whose '^' may show as a
  // line of its own above the '~'s: '^' is the caret line's leftmost mark either way).
  ASSERT_GE(lines.size(), 3u) << "the diagnostic, its source line and its caret line";
  const Line& source = lines[1];
  const Line& caret = lines[2];
  const double advance = double(source.right - source.left + 1) / double(text.size());
  const double column_37 = source.left + 36 * advance;
  EXPECT_NEAR(caret.left, column_37, advance * 0.6)
      << "the caret stands " << (caret.left - column_37) / advance << " characters off column 37";
}

// Counts the saturated pixels of a screenshot's 3D view (vivid modules, the group's rim and labels;
// faded modules, the ground and the background are greyish).
int saturated_pixels(const dw::render::Image& image, const json& view) {
  const int x0 = int(view["x"].get<double>()), y0 = int(view["y"].get<double>());
  int count = 0;
  for (int y = y0; y < std::min(image.height, y0 + int(view["height"])); ++y)
    for (int x = x0; x < std::min(image.width, x0 + int(view["width"])); ++x) {
      const uint8_t* p = image.pixel(x, y);
      if (std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]}) > 60) ++count;
    }
  return count;
}

// No flicker: a watchpoint matching at odd steps only, the ensemble looks the same at a step with
// a match and at one without (it switched from faded to vivid and back at every step).
// Play after a scripted `run 60` and a while goes on from step 60 at its speed (10 steps a
// second): its clock counted the run's time and the wait, and the first frame jumped 60 -> 79.
TEST_F(Window, PlayAfterARunStartsItsClockThen) {
  const Outcome view =
      dwatch("view " + kLeader,
             "action two_leaders log\nrun 60\nwait 40\nkey space\nwait 1\nkey space\npanel position\n", true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 7u) << view.err;
  ASSERT_EQ(view.answers[1]["current"], 60);
  EXPECT_LE(view.answers[6]["current"].get<int64_t>(), 63) << "play jumped";
}

TEST_F(Window, TheEnsembleDoesNotFlickerAsMatchesComeAndGo) {
  std::ofstream(dir_ / "x.lua") << "program = { vars = { \"v\", \"k\" } }\n"
                                   "function step(m) m:set(\"v\", m.step % 2) end\n";
  std::ofstream(dir_ / "s.toml") << "steps = 12\n[lattice]\nkind = \"line\"\nsize = [8]\n[[program]]\n"
                                    "script = \"x.lua\"\n[[watch]]\nname = \"odd\"\n"
                                    "text = \"modules(a); a.v = 1\"\naction = \"log\"\n[view]\ncolor_by = \"k\"\n";
  const Outcome view =
      dwatch("view s.toml", "run\nseek 4\nscreenshot even.png\nseek 5\nscreenshot odd.png\nmatches odd 5\n", true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 6u) << view.err;
  ASSERT_GT(view.answers[5]["matches"].size(), 0u) << "no match at step 5";
  std::string error;
  const auto even = dw::render::read_png((dir_ / "even.png").string(), &error);
  const auto odd = dw::render::read_png((dir_ / "odd.png").string(), &error);
  ASSERT_TRUE(even && odd) << error;
  const int vivid_even = saturated_pixels(*even, view.answers[2]["view"]);
  const int vivid_odd = saturated_pixels(*odd, view.answers[4]["view"]);
  // At step 5 one module is the group (solid, rimmed, labelled); at step 4 none is vivid: only the
  // legend's swatch is.
  EXPECT_LT(vivid_even, vivid_odd) << "the ensemble is vivid at a step without a match";
  EXPECT_LT(vivid_even, 2000);
}

}  // namespace
