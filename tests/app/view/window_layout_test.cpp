// Nothing cut at the sizes users have (issue 64, defect 6), seen on the pixels: each table header's
// text reaches as far right as its whole width ("matc..." in the Watchpoints table at 1600x1000
// stopped short of where "matches" ends).
#include "tests/app/view/window_fixture.h"

namespace {

using namespace dw_window_test;

// The rightmost bright (text) pixel in rows y0..y1 between x0 and x1, or -1.
int rightmost_text(const dw::render::Image& image, int x0, int y0, int x1, int y1) {
  int right = -1;
  for (int y = std::max(0, y0); y < std::min(image.height, y1); ++y)
    for (int x = std::max(0, x0); x < std::min(image.width, x1); ++x) {
      const uint8_t* p = image.pixel(x, y);
      if (std::min({p[0], p[1], p[2]}) > 140) right = std::max(right, x);
    }
  return right;
}

// At three sizes, and before any match (the Matches table's "watch" was "wat..." while empty).
TEST_F(Window, EveryTableHeaderShowsWholeAtEverySize) {
  for (const std::string size : {"", " --width 1280 --height 720", " --width 1920 --height 1080", " --empty"}) {
    const bool empty = size == " --empty";
    const Outcome view = dwatch("view " + kLeader + (empty ? "" : size),
                                empty ? "step\nclick 7\nwait 3\npanel widgets\nscreenshot w.png\n"
                                      : "run\nclick 7\nwait 3\npanel widgets\nscreenshot w.png\n",
                                true);
    ASSERT_EQ(view.exit_code, 0) << size << view.err;
    ASSERT_EQ(view.answers.size(), 5u) << view.err << view.answers.back().dump();
    std::string error;
    const auto image = dw::render::read_png((dir_ / "w.png").string(), &error);
    ASSERT_TRUE(image) << error;
    int headers = 0;
    for (const json& w : view.answers[3]["widgets"]) {
      const std::string name = w["name"];
      if (w["text_width"].get<double>() <= 0 || name.find(": ") == std::string::npos) continue;
      ++headers;
      const json& r = w["rect"];
      const int x0 = int(r[0].get<double>()), y0 = int(r[1].get<double>()), y1 = int(r[3].get<double>());
      const int end = x0 + int(w["text_width"].get<double>());
      // Its text's last columns are inked (a cut header ends in "..." well before them).
      EXPECT_GE(rightmost_text(*image, x0, y0, end + 1, y1), end - 4) << size << ": the header " << name << " is cut";
    }
    EXPECT_GE(headers, 10) << size << ": the Watchpoints', Matches' and variables' headers";
  }
}

}  // namespace

namespace {

// The Statistics panel's small plots say their values: each writes its largest inside it (they
// had none, and "step ms" read 0.000), seen as white text pixels within each plot's frame.
TEST_F(Window, TheStatisticsPlotsWriteTheirValues) {
  const Outcome view = dwatch("view " + kLeader, "run\nwait 3\npanel plots\nscreenshot s.png\n", true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 4u) << view.err;
  const json& all = view.answers[2]["plot_rects"];
  ASSERT_GE(all.size(), 5u) << "the statistics' five plots (after the Module panel's when a module is selected)";
  const json rects(all.end() - 5, all.end());
  std::string error;
  const auto image = dw::render::read_png((dir_ / "s.png").string(), &error);
  ASSERT_TRUE(image) << error;
  for (const json& r : rects) {
    int white = 0;
    for (int y = int(r[1].get<double>()); y < int(r[3].get<double>()); ++y)
      for (int x = int(r[0].get<double>()); x < int(r[2].get<double>()); ++x)
        white += std::min({image->pixel(x, y)[0], image->pixel(x, y)[1], image->pixel(x, y)[2]}) > 220;
    EXPECT_GT(white, 10) << "a statistics plot without its value: " << r;
  }
}

}  // namespace
