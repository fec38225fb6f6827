// `dwatch render SCENARIO --step N --out PNG`: the 3D view of a scenario at one step, headless
// (docs/design.md §6, §9), with the groups its watchpoints matched at that step highlighted.
// `--video FILE [--from A] [--to B]`: steps A..B drawn the same way, one frame each, streamed to an
// H.264 or VP9 video (render/video_writer.h) under one camera.
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "app/cli/commands.h"
#include "app/cli/progress.h"
#include "app/cli/run_summary.h"
#include "render/osmesa_context.h"
#include "render/renderer.h"
#include "render/scene.h"
#include "render/video_writer.h"
#include "shell/integer_option.h"
#include "shell/options.h"
#include "shell/output_files.h"
#include "shell/view_image.h"
#include "sim/session.h"

namespace dw::app {
namespace {

struct RenderArgs {
  std::string scenario, out, video, color_by, highlight = "first";
  std::vector<double> camera_eye, camera_target;  // x, y, z: as the window's camera was
  std::optional<int64_t> step;
  std::optional<int64_t> from, to, fps;  // --video's
  int width = 1280, height = 720;
  bool no_memory_check = false;
};

constexpr int kDefaultFps = 10;  // a step stays on screen long enough to see what changed

// What is wrong with the options, before anything is loaded; empty when nothing is.
std::string options_problem(const RenderArgs& a) {
  if (!a.out.empty() && !a.video.empty())
    return "--out and --video are exclusive: --out draws one step as a PNG, --video the steps --from..--to as a "
           "video";
  if (a.out.empty() && a.video.empty())
    return "render needs --out PNG (one step) or --video FILE.mp4|FILE.webm (a video of steps --from..--to)";
  if (a.out == "-") return "--out needs a file name";
  if (a.video == "-") return "--video needs a file name (its extension, .mp4 or .webm, chooses the codec)";
  if (a.video.empty()) {
    if (a.from || a.to || a.fps) return "--from, --to and --fps are for --video; --out draws the one --step";
    return {};
  }
  if (a.step) return "--step is for --out; a video draws the steps --from A --to B";
  if (a.from && a.to && *a.from > *a.to)
    return "--from " + std::to_string(*a.from) + " is after --to " + std::to_string(*a.to);
  if (a.width % 2 != 0 || a.height % 2 != 0) {
    const bool w = a.width % 2 != 0;
    const int odd = w ? a.width : a.height;
    return std::string(w ? "--width " : "--height ") + std::to_string(odd) +
           ": a video's width and height must be even (H.264 and VP9 keep colour at half resolution, yuv420p); " +
           "say " + std::to_string(odd - 1) + " or " + std::to_string(odd + 1);
  }
  return {};
}

shell::Highlight highlight_named(const std::string& name) {
  return name == "all" ? shell::Highlight::All : name == "none" ? shell::Highlight::None : shell::Highlight::First;
}

// Moves the session onto step t (through any pause) and simulates on until every watchpoint has
// decided it, so that its matches are known. False when a signal stopped it first.
bool go_to(sim::Session& session, int64_t t, const sim::Control& control) {
  while (session.current() < t && !control.stopped()) session.run_until(t + 1, {}, control);
  if (control.stopped()) return false;
  session.decide(t, {}, control);
  return !control.stopped();
}

// Step t as `dwatch render --step t` draws it: its highlighted groups, the step in the title.
render::Scene scene_at(sim::Session& session, int64_t t, shell::Highlight highlight, render::SceneSettings settings,
                       const std::string& name, std::vector<render::SceneGroup>& groups) {
  groups = shell::groups_at(session, t, highlight);
  settings.title = name + "  \xC2\xB7  step " + std::to_string(t);
  return render::build_scene(session.model(), session.state(), groups, settings);
}

// A `count` watchpoint keeps no groups: say so rather than highlight nothing without a word.
void say_counted(const sim::Session& session, shell::Highlight highlight) {
  if (highlight == shell::Highlight::None) return;
  for (const sim::HostedWatchpoint& h : session.watches().hosted())
    if (!sim::lists_matches(h.action))
      std::cout << "  " << h.watchpoint.name
                << " only counts its matches (action = \"count\"), so none of its groups is"
                << " highlighted; set action = \"log\" to see them\n";
}

// The steps --from..--to, one frame each, under the first frame's camera. Frames go to the
// encoder as they are drawn; a signal stops between two, leaving no file.
int render_video(const RenderArgs& args, scenarios::Scenario& scenario, render::SceneSettings settings,
                 shell::Interrupts* interrupts) {
  const int64_t from = args.from.value_or(0), to = args.to.value_or(std::max<int64_t>(0, scenario.steps - 1));
  if (from > to) {
    std::cerr << "dwatch: error: --from " << from << " is after the last step, " << to << " (--to)\n";
    return 2;
  }
  // Its summary goes to standard output: a video written there, or onto the file standard output
  // is, would lose it.
  std::vector<std::string> inputs = scenario.inputs;
  inputs.emplace_back(shell::kStandardOutput);
  if (!shell::check_distinct_files(inputs, {{"--video", args.video}}, "where the summary goes")) return 2;
  const int fps = int(args.fps.value_or(kDefaultFps));
  auto opened = render::VideoWriter::open(args.video, {args.width, args.height, fps});  // a bad path costs no run
  if (auto* error = std::get_if<std::string>(&opened)) {
    std::cerr << "dwatch: error: --video: " << *error << "\n";
    return 2;
  }
  render::VideoWriter& video = *std::get<0>(opened);
  auto context = render::OsMesaContext::create();
  if (auto* error = std::get_if<std::string>(&context)) {
    std::cerr << "dwatch: error: " << *error << "\n";
    return 1;
  }

  const shell::Highlight highlight = highlight_named(args.highlight);
  sim::Session session(*scenario.model, *scenario.world,
                       {scenario.threads, scenario.steps, scenario.history_mb << 20, scenario.events});
  ProgressBar progress("video " + scenario.name, to - from + 1, true);
  // As `run`: a signal stops between two frames, the video left unwritten.
  std::optional<shell::Interrupts::Stoppable> stoppable;
  sim::Control control;
  if (interrupts) {
    stoppable.emplace(*interrupts);
    control.stop = stoppable->token();
  }
  int64_t highlighted_steps = 0;
  std::optional<render::SceneGroup> first_group;
  render::Camera camera;
  try {
    render::Renderer renderer(std::get<0>(context)->gl());
    for (int64_t t = from; t <= to && go_to(session, t, control); ++t) {
      std::vector<render::SceneGroup> groups;
      render::Scene scene = scene_at(session, t, highlight, settings, scenario.name, groups);
      if (t == from) {
        // One camera for the whole video: the first frame's, given or fitted. Fitting each frame
        // would make the view jump as modules move. It is fitted to the picture a frame without a
        // highlighted group leaves it (the renderer gives a group's caption a line of its own, which
        // shrinks the picture): so it fits every frame, and a first frame with no group is drawn
        // as `render --step` draws it.
        render::Scene framing = scene;
        framing.groups.clear();
        if (shell::camera_refused(framing, args.width, args.height)) {
          progress.finish();
          return 2;
        }
        camera = renderer.camera(framing, args.width, args.height);
        settings.camera_eye = scene.camera_eye = sim::Vec3{camera.eye.x, camera.eye.y, camera.eye.z};
        settings.camera_target = scene.camera_target = sim::Vec3{camera.target.x, camera.target.y, camera.target.z};
      }
      if (!groups.empty() && highlighted_steps++ == 0) first_group = groups.front();
      if (std::string error = video.add_frame(renderer.render(scene, args.width, args.height)); !error.empty()) {
        progress.finish();
        std::cerr << "dwatch: error: " << error << "\n";
        return 1;
      }
      progress.update(t - from + 1);
    }
  } catch (const sim::ProgramError& e) {
    progress.finish();
    std::cerr << "dwatch: " << args.scenario << ": error: " << e.what() << "\n";
    return 1;
  } catch (const render::RenderError& e) {
    progress.finish();
    std::cerr << "dwatch: error: " << e.what() << "\n";
    return 1;
  }
  progress.finish();
  // From here on the video is written: a signal now ends the process at once, which leaves the
  // file unwritten (its temporary unnamed) and an older one as it was.
  const std::optional<int> signal = stoppable ? stoppable->signal() : std::nullopt;
  stoppable.reset();
  if (signal) {
    std::cerr << "dwatch: render " << args.scenario << " interrupted (" << shell::Interrupts::name(*signal)
              << ") after " << video.frames() << " of " << to - from + 1 << " frames: nothing written (--video "
              << args.video << ": as it was before)\n";
    return shell::Interrupts::exit_code(*signal);
  }
  if (std::string error = video.finish(); !error.empty()) {
    std::cerr << "dwatch: error: " << error << "\n";
    return 1;
  }
  std::ostringstream eye, target;  // as the options take them, to the float: --step T with these draws frame T
  eye << std::setprecision(9) << camera.eye.x << "," << camera.eye.y << "," << camera.eye.z;
  target << std::setprecision(9) << camera.target.x << "," << camera.target.y << "," << camera.target.z;
  std::cout << "render " << args.scenario << ": steps " << from << ".." << to << ", " << video.frames() << " frames at "
            << fps << " frames/s (" << video.codec() << ")";
  if (!settings.color_by.empty()) std::cout << ", coloured by " << settings.color_by;
  std::cout << ", " << highlighted_steps << (highlighted_steps == 1 ? " step" : " steps")
            << " with a group highlighted -> " << args.video << " (" << args.width << "x" << args.height << ")\n"
            << "  camera: --camera-eye " << eye.str() << " --camera-target " << target.str() << "\n";
  if (first_group)
    std::cout << "  first: " << first_group->watch << " t=" << first_group->t << ": "
              << group_text(first_group->slot_names, first_group->modules) << "\n";
  say_counted(session, highlight);
  return 0;
}

int render_scenario(const RenderArgs& args, shell::Interrupts* interrupts) {
  if (std::string problem = options_problem(args); !problem.empty()) {
    std::cerr << "dwatch: error: " << problem << "\n";
    return 2;
  }
  scenarios::ScenarioOverrides overrides;
  overrides.memory_limit = shell::memory_limit_unless(args.no_memory_check);
  auto loaded = scenarios::load_scenario(args.scenario, overrides);
  if (auto* errors = std::get_if<std::string>(&loaded)) {
    std::cerr << *errors;
    return 2;
  }
  scenarios::Scenario& scenario = std::get<scenarios::Scenario>(loaded);
  const sim::Model& model = *scenario.model;
  if (std::string error = shell::check_color_by(model, args.color_by); !error.empty()) {
    std::cerr << "dwatch: error: " << error << "\n";
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
  render::SceneSettings settings = shell::scene_settings(scenario, args.color_by);
  auto vec = [](const std::vector<double>& v) { return sim::Vec3{float(v[0]), float(v[1]), float(v[2])}; };
  if (!args.camera_eye.empty()) settings.camera_eye = vec(args.camera_eye);
  if (!args.camera_target.empty()) settings.camera_target = vec(args.camera_target);
  if (!args.video.empty()) return render_video(args, scenario, settings, interrupts);
  const shell::NamedFile out_file{"--out", args.out};
  std::unique_ptr<sim::OutputFile> out;               // opened now: a bad path costs no run
  std::vector<std::string> inputs = scenario.inputs;  // and where the summary goes, as for a video
  inputs.emplace_back(shell::kStandardOutput);
  if (!shell::check_distinct_files(inputs, {out_file}, "where the summary goes") || !shell::open_output(out_file, out))
    return 2;
  const int64_t step = args.step.value_or(std::max<int64_t>(0, scenario.steps - 1));

  // The session goes to the step (through any pause) and simulates on until every watchpoint
  // has decided it, so that its matches are known.
  sim::Session session(*scenario.model, *scenario.world,
                       {scenario.threads, scenario.steps, scenario.history_mb << 20, scenario.events});
  try {
    go_to(session, step, {});
  } catch (const sim::ProgramError& e) {
    std::cerr << "dwatch: " << args.scenario << ": error: " << e.what() << "\n";
    return 1;
  }

  const shell::Highlight highlight = highlight_named(args.highlight);
  std::vector<render::SceneGroup> groups;
  const render::Scene scene = scene_at(session, step, highlight, settings, scenario.name, groups);
  if (shell::camera_refused(scene, args.width, args.height)) return 2;
  std::string error = shell::write_view(scene, *out, args.width, args.height);
  if (error.empty()) error = out->commit();
  if (!error.empty()) {
    std::cerr << "dwatch: error: " << error << "\n";
    return 1;
  }
  std::cout << "render " << args.scenario << ": step " << step << ", " << scene.modules.size() << " modules";
  if (!settings.color_by.empty()) std::cout << " coloured by " << settings.color_by;
  std::cout << ", " << groups.size() << (groups.size() == 1 ? " group" : " groups") << " highlighted -> " << args.out
            << " (" << args.width << "x" << args.height << ")\n";
  for (const render::SceneGroup& g : groups)
    std::cout << "  " << g.watch << " t=" << g.t << ": " << group_text(g.slot_names, g.modules) << "\n";
  say_counted(session, highlight);
  return 0;
}

}  // namespace

void add_render_command(CLI::App& app, std::function<int()>& run, shell::Interrupts* interrupts) {
  auto* cmd =
      app.add_subcommand("render", "Draw a scenario's 3D view at one step to a PNG, or steps to a video, headless");
  auto args = std::make_shared<RenderArgs>();
  cmd->add_option("scenario", args->scenario, "Scenario file (TOML)")->required();
  shell::add_integer_option(*cmd, "--step", args->step, {"step", 0, scenarios::kStepsRange.max},
                            "The step to show (default: the scenario's last)");
  cmd->add_option("--out,-o", args->out, "The PNG to write (or --video)");
  cmd->add_option("--video", args->video,
                  "A video of the steps --from..--to instead: .mp4 (H.264) or .webm (VP9), even --width and --height");
  shell::add_integer_option(*cmd, "--from", args->from, {"from", 0, scenarios::kStepsRange.max},
                            "The video's first step (default: 0)");
  shell::add_integer_option(*cmd, "--to", args->to, {"to", 0, scenarios::kStepsRange.max},
                            "The video's last step (default: the scenario's last)");
  shell::add_integer_option(*cmd, "--fps", args->fps, {"fps", 1, 240},
                            "The video's frames (steps) per second (default: 10)");
  shell::add_integer_option(*cmd, "--width", args->width, {"width", 16, 8192}, "Image width in pixels")
      ->default_val(1280);
  shell::add_integer_option(*cmd, "--height", args->height, {"height", 16, 8192}, "Image height in pixels")
      ->default_val(720);
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
  shell::add_memory_check_flag(*cmd, args->no_memory_check);
  cmd->callback([&run, args, interrupts] { run = [args, interrupts] { return render_scenario(*args, interrupts); }; });
}

}  // namespace dw::app
