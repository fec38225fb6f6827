// `dwatch render SCENARIO --step N --out PNG`: the 3D view of a scenario at one step, headless
// (docs/design.md §6, §9), with the groups its watchpoints matched at that step highlighted.
#include <fstream>
#include <iostream>
#include <memory>

#include "app/commands.h"
#include "app/detector_flags.h"
#include "app/integer_option.h"
#include "app/output_files.h"
#include "app/session_script.h"
#include "app/view_image.h"
#include "render/scene.h"
#include "sim/session.h"

namespace dw::app {
namespace {

struct RenderArgs {
  std::string scenario, out, color_by, highlight = "first";
  std::vector<double> camera_eye, camera_target;  // x, y, z: as the window's camera was
  std::optional<int64_t> step;
  int width = 1280, height = 720;
  bool no_memory_check = false;
};

int render_scenario(const RenderArgs& args) {
  scenarios::ScenarioOverrides overrides;
  overrides.memory_limit = memory_limit_unless(args.no_memory_check);
  auto loaded = scenarios::load_scenario(args.scenario, overrides);
  if (auto* errors = std::get_if<std::string>(&loaded)) {
    std::cerr << *errors;
    return 2;
  }
  scenarios::Scenario& scenario = std::get<scenarios::Scenario>(loaded);
  const sim::Model& model = *scenario.model;
  if (std::string error = check_color_by(model, args.color_by); !error.empty()) {
    std::cerr << "dwatch: error: " << error << "\n";
    return 2;
  }
  if (args.out == "-") {
    std::cerr << "dwatch: error: --out needs a file name\n";
    return 2;
  }
  {
    const std::vector<double> eye(args.camera_eye.begin(), args.camera_eye.end()),
        target(args.camera_target.begin(), args.camera_target.end());
    if (std::string problem = scenarios::camera_problem(eye, target); !problem.empty()) {
      std::cerr << "dwatch: error: --camera-eye/--camera-target: " << problem << "\n";
      return 2;
    }
  }
  const NamedFile out_file{"--out", args.out};
  std::unique_ptr<sim::OutputFile> out;  // opened now: a bad path costs no run
  if (!check_distinct_files(scenario.inputs, {out_file}) || !open_output(out_file, out)) return 2;
  const int64_t step = args.step.value_or(std::max<int64_t>(0, scenario.steps - 1));

  // The session goes to the step (through any pause) and simulates on until every watchpoint
  // has decided it, so that its matches are known.
  sim::Session session(*scenario.model, *scenario.world,
                       {scenario.threads, scenario.steps, scenario.history_mb << 20, scenario.events});
  try {
    while (session.current() < step) session.run_until(step + 1);
    session.decide(step);
  } catch (const sim::ProgramError& e) {
    std::cerr << "dwatch: " << args.scenario << ": error: " << e.what() << "\n";
    return 1;
  }

  const Highlight highlight = args.highlight == "all"    ? Highlight::All
                              : args.highlight == "none" ? Highlight::None
                                                         : Highlight::First;
  const std::vector<render::SceneGroup> groups = groups_at(session, step, highlight);
  render::SceneSettings settings = scene_settings(scenario, args.color_by);
  auto vec = [](const std::vector<double>& v) { return sim::Vec3{float(v[0]), float(v[1]), float(v[2])}; };
  if (!args.camera_eye.empty()) settings.camera_eye = vec(args.camera_eye);
  if (!args.camera_target.empty()) settings.camera_target = vec(args.camera_target);
  settings.title = scenario.name + "  \xC2\xB7  step " + std::to_string(step);
  const render::Scene scene = render::build_scene(model, session.state(), groups, settings);
  if (std::string error = write_view(scene, *out, args.width, args.height); !error.empty()) {
    std::cerr << "dwatch: error: " << error << "\n";
    return 1;
  }
  std::cout << "render " << args.scenario << ": step " << step << ", " << scene.modules.size() << " modules";
  if (!settings.color_by.empty()) std::cout << " coloured by " << settings.color_by;
  std::cout << ", " << groups.size() << (groups.size() == 1 ? " group" : " groups") << " highlighted -> " << args.out
            << " (" << args.width << "x" << args.height << ")\n";
  for (const render::SceneGroup& g : groups)
    std::cout << "  " << g.watch << " t=" << g.t << ": " << group_text(g.slot_names, g.modules) << "\n";
  // A `count` watchpoint keeps no groups: say so rather than highlight nothing without a word.
  if (highlight != Highlight::None)
    for (const sim::HostedWatchpoint& h : model.watches)
      if (h.action == sim::MatchAction::Count)
        std::cout << "  " << h.watchpoint.name
                  << " only counts its matches (action = \"count\"), so none of its groups is"
                  << " highlighted; set action = \"log\" to see them\n";
  return 0;
}

}  // namespace

void add_render_command(CLI::App& app, std::function<int()>& run) {
  auto* cmd = app.add_subcommand("render", "Draw a scenario's 3D view at one step to a PNG, headless");
  auto args = std::make_shared<RenderArgs>();
  cmd->add_option("scenario", args->scenario, "Scenario file (TOML)")->required();
  add_integer_option(*cmd, "--step", args->step, {"step", 0, scenarios::kStepsRange.max},
                     "The step to show (default: the scenario's last)");
  cmd->add_option("--out,-o", args->out, "The PNG to write")->required();
  add_integer_option(*cmd, "--width", args->width, {"width", 16, 8192}, "Image width in pixels")->default_val(1280);
  add_integer_option(*cmd, "--height", args->height, {"height", 16, 8192}, "Image height in pixels")->default_val(720);
  cmd->add_option("--color-by", args->color_by, "Colour modules by this variable (default: the scenario's [view])");
  cmd->add_option("--highlight", args->highlight, "Which groups matched at the step to highlight")
      ->check(CLI::IsMember({"first", "all", "none"}))
      ->default_val("first");
  cmd->add_option("--camera-eye", args->camera_eye, "Where the camera is: X,Y,Z (default: the scenario's, or fitted)")
      ->delimiter(',')
      ->expected(3);
  cmd->add_option("--camera-target", args->camera_target,
                  "Where the camera looks: X,Y,Z (default: the ensemble's centre)")
      ->delimiter(',')
      ->expected(3);
  add_memory_check_flag(*cmd, args->no_memory_check);
  cmd->callback([&run, args] { run = [args] { return render_scenario(*args); }; });
}

}  // namespace dw::app
