// `dwatch bench view`: the debugger window's frame rate and responsiveness (needs a display: run
// it under `xvfb-run -a -s "-screen 0 1600x1000x24"` headless). For leader election on cubic
// lattices of 1,000 and 10,000 modules with every panel open:
//   - frames/s while the camera turns every frame, so that the 3D view is redrawn each time;
//   - frames/s while playing as fast as the session steps;
//   - the time from a click on a match row, and on the timeline, until the window shows that step.
// Each figure is given as the median of the runs beside the best one: on a shared machine the best
// alone hides how a frame usually goes.
#include <algorithm>
#include <chrono>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <vector>

#include "app/cli/commands.h"
#include "app/view/debugger.h"
#include "bench/bench.h"

namespace dw::app {
namespace {

using Clock = std::chrono::steady_clock;

std::string scenario_text(int side_x, int side_y, int side_z) {
  return "name = \"bench_view\"\nsteps = 400\nseed = 1\n[lattice]\nkind = \"cubic\"\nsize = [" +
         std::to_string(side_x) + ", " + std::to_string(side_y) + ", " + std::to_string(side_z) +
         "]\n[[program]]\nname = \"leader_election\"\nbug = true\n[[watch]]\nname = \"two_leaders\"\n"
         "text = \"modules(a b c); (a.isLeader = 1) and (c.isLeader = 1)\"\nalgorithm = \"distributed\"\n"
         "action = \"log\"\n[view]\ncolor_by = \"isLeader\"\n";
}

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// A figure measured once per run: its median and its best (the largest rate, the shortest time).
struct Runs {
  bool higher_is_better;
  std::vector<double> values;

  double median() const {
    if (values.empty()) return 0;
    std::vector<double> v = values;
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
  }
  double best() const {
    if (values.empty()) return 0;
    return higher_is_better ? *std::max_element(values.begin(), values.end())
                            : *std::min_element(values.begin(), values.end());
  }
};

// "median (best B)" in the unit's scale.
std::string median_and_best(const Runs& runs, double scale) {
  if (runs.values.empty()) return "n/a";
  std::ostringstream text;
  text << std::fixed << std::setprecision(1) << runs.median() * scale << " (best " << runs.best() * scale << ")";
  return text.str();
}

}  // namespace

int bench_view(const bench::BenchArgs& args) {
  auto window = view::GlfwWindow::create(1600, 1000, "dwatch bench view");
  if (auto* error = std::get_if<std::string>(&window)) {
    std::cerr << "dwatch bench view: error: " << *error << "\n";
    return 1;
  }
  std::cout << "bench view: 1600x1000 window, every panel open; the median of " << args.repeat
            << " runs (the best in brackets)\n";
  std::cout << std::fixed << std::setprecision(1);
  struct Size {
    int x, y, z;
  };
  for (const Size s : {Size{10, 10, 10}, Size{22, 22, 21}}) {
    auto loaded = scenarios::load_scenario_text("bench_view.toml", scenario_text(s.x, s.y, s.z));
    if (auto* errors = std::get_if<std::string>(&loaded)) {
      std::cerr << *errors;
      return 1;
    }
    const scenarios::Scenario& scenario = std::get<scenarios::Scenario>(loaded);
    sim::Session session(*scenario.model, *scenario.world,
                         {args.threads, scenario.steps, scenario.history_mb << 20, scenario.events});
    view::Debugger debugger(scenario, session, *std::get<0>(window), "");
    view::ViewModel& model = debugger.model();
    debugger.send("run 150");
    debugger.settle();
    model.selected = 0;
    model.filter = {};
    debugger.settle();

    Runs orbit_fps{true, {}}, play_fps{true, {}}, play_steps{true, {}}, match_click{false, {}},
        timeline_click{false, {}};
    for (int r = 0; r < args.repeat; ++r) {
      const int frames = 60;
      auto start = Clock::now();
      for (int f = 0; f < frames; ++f) {
        model.camera.orbit(5, 0);
        debugger.frame();
      }
      orbit_fps.values.push_back(frames / seconds_since(start));

      // Playing from step 150 as fast as possible: frames drawn while the worker steps.
      debugger.send("seek 150");
      debugger.settle();
      model.speed = 0;
      model.playing = true;
      start = Clock::now();
      int played = 0;
      while (model.playing && seconds_since(start) < 2.0) {
        debugger.frame();
        ++played;
      }
      model.playing = false;
      const double played_seconds = seconds_since(start);
      play_fps.values.push_back(played / played_seconds);
      debugger.settle();
      play_steps.values.push_back(double(debugger.shown().at.current - 150) / played_seconds);

      // A click on a match row (the last one, far from the current step) until the step shows.
      const view::Readout& shown = debugger.shown();
      if (!shown.match_rows.empty()) {
        const view::MatchRef ref = shown.match_rows[shown.match_rows.size() / 2].ref;
        const int64_t want = shown.match_rows[shown.match_rows.size() / 2].t;
        std::vector<std::string> commands;
        debugger.worker().read([&](sim::Session& ss) { commands = model.on_match_click(ss, ref); });
        start = Clock::now();
        for (const std::string& c : commands) debugger.send(c);
        while (debugger.shown().at.current != want) debugger.frame();
        match_click.values.push_back(seconds_since(start));
      }
      // A click on the timeline at step 37.
      view::Timeline timeline{0, std::max<int64_t>(debugger.shown().at.latest, 0), 0, 1000};
      start = Clock::now();
      for (const std::string& c : model.on_timeline_click(timeline, timeline.x_of(37), debugger.shown().at))
        debugger.send(c);
      while (debugger.shown().at.current != 37) debugger.frame();
      timeline_click.values.push_back(seconds_since(start));
    }
    const uint32_t modules = scenario.model->module_count();
    std::cout << "  " << std::setw(6) << modules << " modules: " << median_and_best(orbit_fps, 1)
              << " frames/s turning the camera, " << median_and_best(play_fps, 1) << " frames/s playing at full speed ("
              << median_and_best(play_steps, 1) << " steps/s), a match click shows its step in "
              << median_and_best(match_click, 1000) << " ms, a timeline click in "
              << median_and_best(timeline_click, 1000) << " ms\n";
  }
  return 0;
}

}  // namespace dw::app
