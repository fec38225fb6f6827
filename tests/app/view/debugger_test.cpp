// The debugger window as a person uses it: `dwatch view --script` drives the real GLFW + ImGui
// window under Xvfb (xvfb-run), and what it shows is checked against the headless paths: the 3D
// view's pixels against `dwatch render` of the same step and camera, the panels' text against
// `dwatch session`'s answers, a timeline click against the step it should land on.
#include <set>

#include "tests/app/view/window_fixture.h"
#include "tests/render/decoded_video.h"

namespace {

using namespace dw_window_test;

TEST_F(Window, PausedOnTwoLeadersSeekBackSelectTheGroupAndScreenshot) {
  const Outcome view = dwatch("view " + kLeader,
                              "run\n"
                              "seek 0\n"
                              "panel position\n"
                              "click timeline 1\n"
                              "click match 0\n"
                              "panel matches\n"
                              "panel inspector\n"
                              "click 17\n"
                              "panel inspector\n"
                              "screenshot window.png\n",
                              true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 10u) << view.err;
  const json& paused = view.answers[0];
  ASSERT_TRUE(paused.contains("paused")) << paused;
  const int64_t t = paused["paused"]["t"];
  EXPECT_EQ(view.answers[2]["current"], 0);
  // The timeline click at step t lands on step t.
  EXPECT_EQ(view.answers[3]["current"], t);
  // The first match row is the paused group: selecting it selects its first slot.
  EXPECT_EQ(view.answers[4]["current"], t);
  EXPECT_EQ(view.answers[4]["selected"], paused["paused"]["group"]["a"]);

  // The panels show what the headless session answers at the same step.
  const Outcome session =
      dwatch("session " + kLeader,
             "run\nmatches two_leaders " + std::to_string(t) + "\nstate " +
                 std::to_string(int(paused["paused"]["group"]["a"])) + "\nseek " + std::to_string(t - 1) + "\nstate " +
                 std::to_string(int(paused["paused"]["group"]["a"])) + "\n",
             false);
  ASSERT_EQ(session.exit_code, 0) << session.err;
  const json& table = view.answers[5];
  const json& listed = session.answers[1]["matches"];
  ASSERT_EQ(table["total"], paused["paused"]["matches"]);
  ASSERT_EQ(table["rows"].size(), listed.size());
  for (size_t i = 0; i < listed.size(); ++i) {
    std::string slots;
    for (auto it = listed[i]["slots"].begin(); it != listed[i]["slots"].end(); ++it)
      slots += (slots.empty() ? "" : " ") + it.key() + "=" + std::to_string(int(it.value()));
    EXPECT_EQ(table["rows"][i]["slots"], slots) << "row " << i;
    EXPECT_EQ(table["rows"][i]["t"], t);
  }
  const json& inspector = view.answers[6];
  const json& now = session.answers[2]["vars"];
  const json& before = session.answers[4]["vars"];
  EXPECT_EQ(inspector["module"], paused["paused"]["group"]["a"]);
  for (const json& v : inspector["vars"]) {
    EXPECT_EQ(v["value"], now[v["name"].get<std::string>()]) << v;
    EXPECT_EQ(v["before"], before[v["name"].get<std::string>()]) << v;
    EXPECT_EQ(v["changed"], v["value"] != v["before"]);
  }
  EXPECT_EQ(inspector["nbrs"], session.answers[2]["nbrs"]);
  // A click where module 17 shows selects it (picking).
  EXPECT_EQ(view.answers[7]["selected"], 17);
  EXPECT_EQ(view.answers[8]["module"], 17);

  // The 3D view's pixels are `dwatch render` of the same step and camera.
  const json& shot = view.answers[9];
  const int x = int(shot["view"]["x"].get<double>()), y = int(shot["view"]["y"].get<double>());
  const int w = shot["view"]["width"], h = shot["view"]["height"];
  const auto expected = render_as_shot(shot, t, w, h);
  ASSERT_TRUE(expected);
  std::string error;
  const auto window = dw::render::read_png((dir_ / "window.png").string(), &error);
  ASSERT_TRUE(window) << error;
  ASSERT_LE(x + w, window->width);
  ASSERT_LE(y + h, window->height);
  dw::render::Image crop(w, h);
  for (int row = 0; row < h; ++row) std::copy_n(window->pixel(x, y + row), size_t(w) * 4, crop.pixel(0, row));
  // Around module 17, the selection's ring, which `dwatch render` (no selection) does not draw; it
  // is drawn over whatever covers it, the rims of the group's modules beside it included.
  const int sx = int(view.answers[7]["pixel"][0].get<double>()) - x;
  const int sy = int(view.answers[7]["pixel"][1].get<double>()) - y;
  for (int row = std::max(0, sy - 120); row < std::min(h, sy + 120); ++row)
    for (int col = std::max(0, sx - 120); col < std::min(w, sx + 120); ++col)
      std::copy_n(expected->pixel(col, row), 4, crop.pixel(col, row));
  const auto d = dw::render::compare_images(*expected, crop, kTolerance);
  EXPECT_LE(d.share, 0.001) << d.differing << " pixels differ, the largest by " << d.largest << " (see "
                            << (dir_ / "diff.png").string() << ")";
  if (d.share > 0.001) dw::render::write_png((dir_ / "diff.png").string(), d.diff);
  // The rest of the window is not the 3D view: the panels are there.
  EXPECT_GT(window->width, w + 200);
}

// The selected module shows in 3D beside a highlighted group: a module outside the group, faded
// before the click, is drawn solid with a green rim after it (seen by the screenshot's pixels).
TEST_F(Window, TheSelectedModuleIsVisibleBesideTheGroup) {
  const Outcome view = dwatch("view " + kLeader, "run\nscreenshot before.png\nclick 30\nscreenshot after.png\n", true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 4u) << view.err;
  ASSERT_EQ(view.answers[2]["selected"], 30);
  const auto group = view.answers[0]["paused"]["group"];
  for (const auto& [slot, module] : group.items()) ASSERT_NE(module, 30) << "module 30 must lie outside the group";
  std::string error;
  const auto before = dw::render::read_png((dir_ / "before.png").string(), &error);
  const auto after = dw::render::read_png((dir_ / "after.png").string(), &error);
  ASSERT_TRUE(before && after) << error;
  // Green rim pixels (the renderer's kSelectedOutline, shaded) within 40 pixels of the click.
  const int cx = int(view.answers[2]["pixel"][0].get<double>()), cy = int(view.answers[2]["pixel"][1].get<double>());
  auto green = [&](const dw::render::Image& image) {
    int count = 0;
    for (int y = std::max(0, cy - 40); y < std::min(image.height, cy + 40); ++y)
      for (int x = std::max(0, cx - 40); x < std::min(image.width, cx + 40); ++x) {
        const uint8_t* p = image.pixel(x, y);
        if (p[1] > 150 && p[0] < 90 && p[2] < 110) ++count;
      }
    return count;
  };
  EXPECT_LT(green(*before), 10) << "green around module 30 before it was selected";
  EXPECT_GT(green(*after), 150) << "the selected module has no visible rim";
}

// The Module panel's plot and the Statistics plots have a real width and draw their lines
// (ImGui 1.86 drew them one pixel wide when given a width of -1).
TEST_F(Window, ThePlotsAreDrawnAcrossTheirPanels) {
  const Outcome view = dwatch("view " + kLeader, "run 30\nclick 7\nwait 3\npanel plots\nscreenshot w.png\n", true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 5u) << view.err;
  const json& rects = view.answers[3]["plot_rects"];
  ASSERT_EQ(rects.size(), 6u) << view.answers[3];  // the Module panel's, and five per watchpoint
  std::string error;
  const auto shot = dw::render::read_png((dir_ / "w.png").string(), &error);
  ASSERT_TRUE(shot) << error;
  for (const json& r : rects) {
    const int x0 = int(r[0].get<double>()), y0 = int(r[1].get<double>()), x1 = int(r[2].get<double>()),
              y1 = int(r[3].get<double>());
    EXPECT_GE(x1 - x0, 60) << r << ": a plot a sliver wide";
    ASSERT_LE(x1, shot->width);
    ASSERT_LE(y1, shot->height);
    // ImGui's plot colours (lines grey, histogram yellow) against the frame's dark blue.
    int drawn = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const uint8_t* p = shot->pixel(x, y);
        if ((p[0] > 120 && p[1] > 120) || (p[0] > 180 && p[1] > 120 && p[2] < 80)) ++drawn;
      }
    EXPECT_GE(drawn, 40) << r << ": nothing drawn in the plot";
  }
}

// The timeline shows what is simulated, not the scenario's 200 steps: the simulated band covers
// the share of the timeline the panel says, in the screenshot's pixels; it zooms to a range, a
// click there lands on its step, and it fits again.
TEST_F(Window, TheTimelineCoversTheSimulatedStepsAndZooms) {
  const Outcome view =
      dwatch("view " + kLeader,
             "run\npanel timeline\nscreenshot t.png\naction two_leaders log\ncontinue\ntimeline 100 119\n"
             "click timeline 110\npanel timeline\ntimeline fit\npanel timeline\n",
             true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 10u) << view.err;
  const int64_t latest = view.answers[0]["latest"];
  const json& fitted = view.answers[1];
  EXPECT_EQ(fitted["first"], 0);
  EXPECT_GE(fitted["last"], latest);
  EXPECT_LE(fitted["last"], latest + 8) << "a few steps simulated must not be drawn across 200";
  std::string error;
  const auto shot = dw::render::read_png((dir_ / "t.png").string(), &error);
  ASSERT_TRUE(shot) << error;
  const int x0 = int(fitted["x0"].get<double>()), width = int(fitted["width"].get<double>());
  const int y = int(fitted["y0"].get<double>()) + 1;  // above the lanes' marks
  int band = 0;
  for (int x = x0; x < x0 + width; ++x) {
    const uint8_t* p = shot->pixel(x, y);
    if (std::abs(p[0] - 60) <= 3 && std::abs(p[1] - 62) <= 3 && std::abs(p[2] - 70) <= 3) ++band;
  }
  const double share = double(latest + 1) / double(fitted["last"].get<int64_t>() + 1);
  EXPECT_NEAR(band, share * width, 4.0) << "the simulated steps' band in the screenshot";
  EXPECT_GT(band, width / 4);

  // two_leaders matches at every step: made a log watchpoint, the run goes on to the end.
  EXPECT_EQ(view.answers[4]["paused"], nullptr);
  EXPECT_EQ(view.answers[4]["current"], 199);
  EXPECT_EQ(view.answers[5]["first"], 100);
  EXPECT_EQ(view.answers[5]["last"], 119);
  EXPECT_EQ(view.answers[6]["current"], 110) << "a click on the zoomed timeline";
  EXPECT_EQ(view.answers[7]["fitted"], false);
  EXPECT_EQ(view.answers[7]["first"], 100);
  EXPECT_EQ(view.answers[9]["fitted"], true);
  EXPECT_EQ(view.answers[9]["first"], 0);
  EXPECT_EQ(view.answers[9]["last"], 199);
}

TEST_F(Window, KeysStepSeekAndFindTheNextMatch) {
  const Outcome view =
      dwatch("view " + kLeader,
             "key right\nkey right\nkey right\nkey left\nkey home\nkey n\npanel position\nkey f1\nwait 2\n", true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 9u);
  EXPECT_EQ(view.answers[0]["current"], 0);
  EXPECT_EQ(view.answers[1]["current"], 1);
  EXPECT_EQ(view.answers[2]["current"], 2);
  EXPECT_EQ(view.answers[3]["current"], 1);  // back is a seek
  EXPECT_EQ(view.answers[4]["current"], 0);
  // N: the next step with a two_leaders match after step 0 (step 1 on this scenario, as the
  // session's own run pauses there).
  const Outcome session = dwatch("session " + kLeader, "run\n", false);
  ASSERT_EQ(session.exit_code, 0);
  EXPECT_EQ(view.answers[5]["current"], session.answers[0]["paused"]["t"]);
}

// A watchpoint with actions, added as the editor's Add sends it, acts in the window as in a
// session (the same state hash); the window saves the session as a scenario that runs the same
// branch; and its screenshot may not overwrite an input, the script included.
TEST_F(Window, AnActionWatchpointAndASaveAreTheSessionsAndTheScriptIsAnInput) {
  const std::string commands =
      "watch demote centralized log modules(a b); (a.isLeader = 1) and (b.isLeader = 1) then set a.isLeader = 0\n"
      "run 12\nhash\nsave saved.toml\n";
  const Outcome session = dwatch("session " + kLeader, commands, false);
  ASSERT_EQ(session.exit_code, 0) << session.err;
  fs::remove(dir_ / "saved.toml");  // the window's save makes it anew
  const Outcome view = dwatch("view " + kLeader, commands + "panel watchpoints\nscreenshot script\n", true);
  EXPECT_EQ(view.exit_code, 1) << view.err;
  ASSERT_EQ(view.answers.size(), 5u) << view.err;
  EXPECT_EQ(view.answers[2]["hash"], session.answers[2]["hash"]);
  EXPECT_EQ(view.answers[3]["save"], "saved.toml");
  EXPECT_EQ(view.answers[4]["rows"][1]["name"], "demote");
  EXPECT_NE(view.err.find("screenshot script would overwrite the input script"), std::string::npos) << view.err;
  EXPECT_NE(slurp(dir_ / "script").find("screenshot script"), std::string::npos) << "the script was overwritten";
  // The saved scenario runs the branch: its simulation at step 11 is the session's.
  const Outcome again = dwatch("session saved.toml", "run 12\nhash\n", false);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(again.answers[1]["hash"], session.answers[2]["hash"]);
}

TEST_F(Window, ScriptMistakesAreBadInputAndFailuresStopTheScript) {
  // Every line is checked before the window does anything: the window's own commands too.
  const Outcome bad = dwatch("view " + kLeader, "step\nkey\nseek x\nwait 1 2\n", true);
  EXPECT_EQ(bad.exit_code, 2) << bad.err;
  EXPECT_TRUE(bad.answers.empty());
  EXPECT_NE(bad.err.find("script:2:4: error: key NAME: one of space"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("script:3:6: error:"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("script:4:8: error: 'wait' takes 1 more word"), std::string::npos) << bad.err;
  // A command that cannot be carried out stops the script there.
  const Outcome failed = dwatch("view " + kLeader, "step\nclick match 5000\nstep\n", true);
  EXPECT_EQ(failed.exit_code, 1) << failed.err;
  EXPECT_EQ(failed.answers.size(), 1u);
  // (No match yet at step 0: the list is empty, which it says rather than "from 0 to -1".)
  EXPECT_NE(failed.err.find("script:2: error: there is no ROW to choose: the list is empty"), std::string::npos)
      << failed.err;
}

// A Lua script's error in the window: the run stands at the last step that went through and the
// position panel names the failure; the fixed script, reloaded, runs on from there.
TEST_F(Window, AScriptErrorIsShownAndTheFixedScriptReloaded) {
  const std::string header = "program = { vars = { \"v\" } }\n";
  std::ofstream(dir_ / "x.lua") << header + "function step(m)\n  if m.step == 6 then error('boom') end\nend\n";
  std::ofstream(dir_ / "s.toml")
      << "steps = 20\n[lattice]\nkind = \"line\"\nsize = [4]\n[[program]]\nscript = \"x.lua\"\n";
  const Outcome failed = dwatch("view s.toml", "run\n", true);
  EXPECT_EQ(failed.exit_code, 1) << failed.err;
  EXPECT_NE(failed.err.find("x.lua on module 0 at step 6: x.lua:3: boom"), std::string::npos) << failed.err;

  std::ofstream(dir_ / "x.lua") << header + "function step(m) m:set(\"v\", m.step) end\n";
  const Outcome fixed = dwatch("view s.toml", "run 5\nseek 3\nreload\npanel position\nrun\n", true);
  ASSERT_EQ(fixed.exit_code, 0) << fixed.err;
  ASSERT_EQ(fixed.answers.size(), 5u) << fixed.err;
  EXPECT_EQ(fixed.answers[2]["reloaded"], json::array({"x.lua"}));
  EXPECT_EQ(fixed.answers[2]["from"], 4);
  EXPECT_EQ(fixed.answers[3]["latest"], 3) << "the future after the current step is dropped";
  EXPECT_FALSE(fixed.answers[3].contains("failure"));
  EXPECT_EQ(fixed.answers[4]["current"], 19);
}

}  // namespace

namespace {

// Counts the pixels of a region that are the status line's red (failures).
int red_pixels(const dw::render::Image& image, int x0, int y0, int x1, int y1) {
  int count = 0;
  for (int y = std::max(0, y0); y < std::min(image.height, y1); ++y)
    for (int x = std::max(0, x0); x < std::min(image.width, x1); ++x) {
      const uint8_t* p = image.pixel(x, y);
      if (p[0] > 200 && p[1] < 130 && p[2] < 120) ++count;
    }
  return count;
}

const std::string kBothLeaders = "modules(a b); a.isLeader = 1 and b.isLeader = 1";

// What a user clicks and types, a script reaches through the same input path: the editor's Add,
// the matches' and the session's files, and a failure shown in red while the script goes on.
TEST_F(Window, ScriptsPressButtonsAndTypeIntoFieldsAsAPersonDoes) {
  const Outcome view = dwatch("view " + kLeader,
                              "run 3\n"
                              "type name both\n"
                              "type text " +
                                  kBothLeaders +
                                  "\n"
                                  "press Add\n"
                                  "panel watchpoints\n"
                                  "type matches-file m.jsonl\n"
                                  "press save the matches\n"
                                  "type scenario-file saved scenario.toml\n"  // sent quoted
                                  "press save as scenario\n"
                                  "expect-failure seek 500\n"
                                  "screenshot fail.png\n"
                                  "expect-failure press Launch\n"
                                  "press save as scenario\n"  // the file is there now
                                  "press overwrite it\n",
                              true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 14u) << view.err;
  EXPECT_EQ(view.answers[3]["button"], "Add");
  // The watchpoint typed and added is the session's own: the same matches as `watch` there.
  const Outcome session =
      dwatch("session " + kLeader, "run 3\nwatch both distributed log " + kBothLeaders + "\nmatches\n", false);
  ASSERT_EQ(session.exit_code, 0) << session.err;
  const json& rows = view.answers[4]["rows"];
  ASSERT_EQ(rows.size(), 2u) << view.answers[4];
  EXPECT_EQ(rows[1]["name"], "both");
  EXPECT_EQ(rows[1]["matches"], session.answers[1]["matches"]);
  // Every match, as the match log writes them, in the file typed.
  std::ifstream saved(dir_ / "m.jsonl");
  std::vector<json> lines;
  for (std::string line; std::getline(saved, line);) lines.push_back(json::parse(line));
  EXPECT_EQ(lines.size(), session.answers[2]["count"].get<size_t>());
  EXPECT_EQ(view.answers[6]["status"], "saved " + std::to_string(lines.size()) + " matches -> m.jsonl");
  // The scenario saved from the window has both watchpoints.
  const Outcome reloaded = dwatch("session 'saved scenario.toml'", "status\n", false);
  ASSERT_EQ(reloaded.exit_code, 0) << reloaded.err;
  ASSERT_EQ(reloaded.answers[0]["watches"].size(), 2u);
  EXPECT_EQ(reloaded.answers[0]["watches"][1]["name"], "both");
  // The failure the script expected: its words, in the status line, in red on the screenshot.
  EXPECT_NE(view.answers[9]["failed"].get<std::string>().find("has not been simulated"), std::string::npos);
  EXPECT_NE(view.answers[9]["status"].get<std::string>().find("has not been simulated"), std::string::npos);
  std::string error;
  const auto shot = dw::render::read_png((dir_ / "fail.png").string(), &error);
  ASSERT_TRUE(shot) << error;
  const json& v = view.answers[10]["view"];
  const int below = int(v["y"].get<double>()) + int(v["height"]);
  EXPECT_GT(red_pixels(*shot, 0, below, int(v["width"]), shot->height), 300) << "no red failure line";
  // A button the window does not have: the failure lists those it has.
  EXPECT_NE(view.answers[11]["failed"].get<std::string>().find("no button 'Launch' is in the window now (there are: "),
            std::string::npos);
  // Saving again asks first; the button that confirms it names the file, spaces and all.
  EXPECT_NE(view.answers[12]["status"].get<std::string>().find(
                "saved scenario.toml exists; 'save \"saved scenario.toml\" overwrite' replaces it"),
            std::string::npos)
      << view.answers[12];
  EXPECT_EQ(view.answers[13]["status"].get<std::string>().rfind("saved the session as saved scenario.toml (", 0), 0u)
      << view.answers[13];

  // A command expected to fail that goes through stops the script.
  const Outcome wrong = dwatch("view " + kLeader, "expect-failure step 1\nhash\n", true);
  EXPECT_EQ(wrong.exit_code, 1);
  EXPECT_NE(wrong.err.find("script:1: error: expected to fail, but it went through"), std::string::npos) << wrong.err;
  EXPECT_EQ(wrong.answers.size(), 0u);
}

// Every button, field, table header and watchpoint name shows whole at 1280x720, at the default
// 1600x1000, at 1920x1080 and at 1024x640 (with a watchpoint named long, the module panel filled);
// Set, Remove and "save as scenario" are in sight without scrolling (they were below the Module
// panel's fold at every size); below 1024x640 the window says it is too small.
TEST_F(Window, NothingIsCutAndTheInterventionsAreInSightAtEverySize) {
  for (const std::string size :
       {"", " --width 1280 --height 720", " --width 1920 --height 1080", " --width 1024 --height 640"}) {
    const Outcome view = dwatch("view " + kLeader + size,
                                "run 5\nclick 7\ntype name leaders_side_by_side\ntype text " + kBothLeaders +
                                    "\npress Add\nwait 2\npanel widgets\n",
                                true);
    ASSERT_EQ(view.exit_code, 0) << size << view.err;
    ASSERT_EQ(view.answers.size(), 7u) << view.err;
    const json& panel = view.answers[6];
    EXPECT_EQ(panel["window"]["too_small"], false) << size;
    EXPECT_EQ(panel["cut_labels"], json::array()) << size;
    ASSERT_GT(panel["widgets"].size(), 20u);
    std::set<std::string> in_sight;
    for (const json& w : panel["widgets"]) {
      EXPECT_FALSE(w["cut"].get<bool>()) << size << ": " << w;
      if (!w["out_of_sight"].get<bool>()) in_sight.insert(w["name"].get<std::string>());
    }
    for (const char* name : {"Set", "Remove module", "save as scenario", "value", "scenario-file"})
      EXPECT_TRUE(in_sight.count(name)) << size << ": " << name << " is out of sight";
  }
  const Outcome small = dwatch("view " + kLeader + " --width 900 --height 600", "panel widgets\n", true);
  ASSERT_EQ(small.exit_code, 0) << small.err;
  EXPECT_EQ(small.answers[0]["window"]["too_small"], true);
}

// A pause and a chosen match show their group without cutting off the rest of the ensemble (the
// camera used to centre on the group, and a group at the lattice's edge pushed half of it out).
TEST_F(Window, APauseShowsTheGroupAndTheWholeEnsemble) {
  // Row 188: a=15 b=3 c=2 at step 3, a group on the lattice's bottom edge (centred on, the view
  // lost two modules on the far side).
  const Outcome view = dwatch("view " + kLeader,
                              "run\nscreenshot a.png\naction two_leaders log\nrun 5\nclick match 188\n"
                              "screenshot b.png\n",
                              true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 6u) << view.err;
  ASSERT_EQ(view.answers[4]["selected"], 15) << "the case's group moved: pick another row at the edge";
  for (const json* shot : {&view.answers[1], &view.answers[5]}) {
    const json& in = (*shot)["in_view"];
    EXPECT_EQ(in["modules"], in["of"]) << *shot;
    EXPECT_GT(in["group_of"], 0) << *shot;
    EXPECT_EQ(in["group"], in["group_of"]) << *shot;
  }
}

// The README's walkthrough of the window, every step of it, through the buttons, keys, clicks and
// fields it names; what it claims is checked against `dwatch session`, and its figures against
// what the window shows.
TEST_F(Window, TheReadmeWalkthroughRunsAsWritten) {
  const std::string leaders = "modules(a b c); (a.isLeader = 1) and (c.isLeader = 1)";
  const Outcome view = dwatch("view " + kLeader,
                              "press Run\n"                                            // 1. Run: paused, the group lit
                              "key left\nkey home\nclick timeline 1\n"                 // 2. scrub back and forth
                              "click 7\npanel inspector\nclick 17\npanel inspector\n"  // modules a and c
                              "type name leaders_ordered\ntype text " +
                                  leaders +
                                  "\n"  // 3. the editor
                                  "press algorithm\npress algorithm: centralized\npress Add\npanel watchpoints\n"
                                  "click 7\ntype value 0\npress Set\n"  // 4. a fix in place
                                  "type scenario-file leader_election-branch.toml\npress save as scenario\n",
                              true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 19u) << view.err;
  const Outcome session =
      dwatch("session " + kLeader, "run\nwatch leaders_ordered centralized log " + leaders + "\n", false);
  ASSERT_EQ(session.exit_code, 0) << session.err;
  const json& paused = session.answers[0]["paused"];
  const int64_t t = paused["t"];
  // 1. The run stops at the first match's step, its group selected.
  EXPECT_EQ(view.answers[0]["current"], t);
  EXPECT_EQ(view.answers[0]["status"].get<std::string>().rfind("paused at step " + std::to_string(t), 0), 0u);
  // 2. Left is a seek back, Home step 0, the timeline click its step.
  EXPECT_EQ(view.answers[1]["current"], t - 1);
  EXPECT_EQ(view.answers[2]["current"], 0);
  EXPECT_EQ(view.answers[3]["current"], 1);
  ASSERT_EQ(t, 1) << "the walkthrough's clicks assume the pause at step 1";
  // a and c both became leaders at this step (each compared priorities with its 1-hop neighbours).
  for (const size_t i : {5u, 7u}) {
    const json& inspector = view.answers[i];
    EXPECT_EQ(inspector["module"], i == 5 ? paused["group"]["a"] : paused["group"]["c"]);
    EXPECT_EQ(inspector["vars"][0]["name"], "isLeader");
    EXPECT_EQ(inspector["vars"][0]["value"], 1);
    EXPECT_EQ(inspector["vars"][0]["before"], 0);
  }
  // 3. The centralized reading added from the editor: the session's matches, and the README's figures.
  const json& rows = view.answers[13]["rows"];
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1]["algorithm"], "centralized");
  EXPECT_EQ(rows[1]["matches"], session.answers[1]["matches"]);
  std::string readme;  // its words, one space between each
  for (const char c : slurp(fs::path(DWATCH_SCENARIOS_DIR) / ".." / "README.md"))
    if (!std::isspace(static_cast<unsigned char>(c))) readme += c;
    else if (!readme.empty() && readme.back() != ' ') readme += ' ';
  const std::string figures = "(" + std::to_string(rows[1]["matches"].get<int64_t>()) + " by step " +
                              std::to_string(session.answers[1]["decided"].get<int64_t>()) +
                              ", against the distributed one's " + std::to_string(rows[0]["matches"].get<int64_t>()) +
                              ")";
  EXPECT_NE(readme.find(figures), std::string::npos) << "README's figures are not the window's: " << figures;
  // 4. Set: a branch from the next step; saved as a scenario that replays it headless.
  EXPECT_EQ(view.answers[16]["status"].get<std::string>().rfind("intervention at step 2", 0), 0u);
  EXPECT_EQ(view.answers[18]["status"],
            "saved the session as leader_election-branch.toml (2 watchpoints, 1 intervention)");
  const std::string saved = slurp(dir_ / "leader_election-branch.toml");
  EXPECT_NE(saved.find("[[event]]\nat = 2\nmodule = 7\nset = { isLeader = 0 }"), std::string::npos) << saved;
  const std::string run = "cd " + dir_.string() + " && " + DWATCH_EXE + " run leader_election-branch.toml >/dev/null";
  EXPECT_EQ(std::system(run.c_str()), 0);
}

// Record: a video of the steps as they show, one frame each, the first drawn as `dwatch render`
// draws that step with the same camera (within the codec's loss), the group in red.
TEST_F(Window, RecordWritesAFramePerStepShown) {
  const Outcome view = dwatch("view " + kLeader,
                              "run 3\nscreenshot first.png\ntype video-file v.mp4\npress Record\nstep 1\nstep 1\n"
                              "press Stop recording\n",
                              true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 7u) << view.err;
  EXPECT_EQ(view.answers[6]["status"], "recorded 3 frames (H.264) -> v.mp4");
  const auto video = dw::render::test::decode_video((dir_ / "v.mp4").string());
  ASSERT_EQ(video.error, "");
  EXPECT_EQ(video.codec, "h264");
  ASSERT_EQ(video.frames.size(), 3u);
  const json& shot = view.answers[1];
  const int w = int(shot["view"]["width"]) & ~1, h = int(shot["view"]["height"]) & ~1;
  EXPECT_EQ(video.width, w);
  EXPECT_EQ(video.height, h);
  const auto expected = render_as_shot(shot, 1, w, h);
  ASSERT_TRUE(expected);
  const dw::render::Image& first = video.frames[0];
  double difference = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) difference += std::abs(int(first.pixel(x, y)[c]) - int(expected->pixel(x, y)[c]));
  EXPECT_LT(difference / (double(w) * h * 3), 4.0) << "the first frame is not the step as render draws it";
  EXPECT_GT(red_pixels(first, 0, 0, w, h), 200) << "the paused group's red highlight";
}

}  // namespace

// A screencast films the whole window, panels and all, a frame per script line and N for `wait N`:
// the last frame is the window's screenshot of that moment (within the codec's loss), at the
// window's size; one the script did not stop ends with it, and `stop` without one is refused.
TEST_F(Window, AScreencastFilmsTheWholeWindowAFramePerLine) {
  const Outcome view = dwatch("view " + kLeader,
                              "screencast s.mp4\nrun\nwait 4\nscreenshot paused.png\nscreencast stop\n"
                              "expect-failure screencast stop\nscreencast t.webm\nstep 1\n",
                              true);
  ASSERT_EQ(view.exit_code, 0) << view.err;
  ASSERT_EQ(view.answers.size(), 8u) << view.err;
  EXPECT_EQ(view.answers[4]["frames"], 6) << "run, 4 for wait 4, screenshot";
  EXPECT_EQ(view.answers[5]["failed"], "no screencast is being filmed ('screencast FILE' starts one)");
  std::string error;
  const auto shot = dw::render::read_png((dir_ / "paused.png").string(), &error);
  ASSERT_TRUE(shot) << error;
  const auto video = dw::render::test::decode_video((dir_ / "s.mp4").string());
  ASSERT_EQ(video.error, "");
  ASSERT_EQ(video.frames.size(), 6u);
  EXPECT_EQ(video.width, shot->width & ~1);
  EXPECT_EQ(video.height, shot->height & ~1);
  const dw::render::Image& last = video.frames.back();
  double difference = 0;
  for (int y = 0; y < video.height; ++y)
    for (int x = 0; x < video.width; ++x)
      for (int c = 0; c < 3; ++c) difference += std::abs(int(last.pixel(x, y)[c]) - int(shot->pixel(x, y)[c]));
  EXPECT_LT(difference / (double(video.width) * video.height * 3), 4.0) << "the last frame is not the window";
  // The unstopped screencast: a frame for `step 1`, in place when the script ended.
  const auto unstopped = dw::render::test::decode_video((dir_ / "t.webm").string());
  ASSERT_EQ(unstopped.error, "");
  EXPECT_EQ(unstopped.frames.size(), 1u);
}
