// `dwatch view SCENARIO [--script FILE]`: the debugger window (DESIGN §6, §7a). Without a script
// it is the interactive window until closed; with one, the script drives the real window and
// each line is answered with one JSON line, as `dwatch session` answers.
#include <iostream>
#include <memory>

#include "app/commands.h"
#include "app/integer_option.h"
#include "app/view/debugger.h"
#include "sim/read_file.h"

namespace dw::app {
namespace {

struct ViewArgs {
  std::string scenario, script;
  std::optional<int64_t> seed, threads, history_mb;
  int width = 1600, height = 1000;
  bool keep_layout = true;
};

int view_main(const ViewArgs& args) {
  scenarios::ScenarioOverrides overrides;
  if (args.seed) overrides.seed = static_cast<uint64_t>(*args.seed);
  auto loaded = scenarios::load_scenario(args.scenario, overrides);
  if (auto* errors = std::get_if<std::string>(&loaded)) {
    std::cerr << *errors;
    return 2;
  }
  const scenarios::Scenario& scenario = std::get<scenarios::Scenario>(loaded);
  std::optional<watch::SourceText> script;
  if (!args.script.empty()) {
    std::string error;
    auto text = sim::read_file(args.script, &error);
    if (!text) {
      std::cerr << args.script << ": error: " << error << " (the script)\n";
      return 2;
    }
    script.emplace(args.script, std::move(*text));
  }
  auto window = view::GlfwWindow::create(args.width, args.height, "dwatch view  " + scenario.name);
  if (auto* error = std::get_if<std::string>(&window)) {
    std::cerr << "dwatch view: error: " << *error << "\n";
    return 1;
  }
  sim::Session session(
      *scenario.model, *scenario.world,
      {.threads = args.threads ? static_cast<unsigned>(*args.threads) : scenario.threads,
       .end = scenario.steps,
       .history_bytes = (args.history_mb ? static_cast<size_t>(*args.history_mb) : scenario.history_mb) << 20,
       .events = scenario.events});
  // A script gets the default layout, whatever the user's own file says: its screenshots must
  // not depend on how someone arranged the panels.
  view::Debugger debugger(scenario, session, *std::get<0>(window),
                          script || !args.keep_layout ? std::string() : view::layout_file());
  return script ? debugger.run_script(*script) : debugger.run_interactive();
}

}  // namespace

void add_view_command(CLI::App& app, std::function<int()>& run) {
  auto* cmd = app.add_subcommand("view", "The debugger window: 3D view, timeline, watchpoints, matches, inspector");
  auto args = std::make_shared<ViewArgs>();
  cmd->add_option("scenario", args->scenario, "Scenario file (TOML)")->required();
  cmd->add_option("--script", args->script,
                  "Drive the window with commands: the session's, plus click M | click match ROW | click timeline T, "
                  "key NAME, wait N, screenshot FILE, panel NAME");
  add_integer_option(*cmd, "--seed", args->seed, scenarios::kSeedRange, "Random seed (default: the scenario's)");
  add_integer_option(*cmd, "--threads,-j", args->threads, scenarios::kThreadsRange,
                     "Threads stepping modules (results never depend on it)");
  add_integer_option(*cmd, "--history-mb", args->history_mb, scenarios::kHistoryRange,
                     "Memory for the history's keyframes, in MiB (default: the scenario's)");
  add_integer_option(*cmd, "--width", args->width, {"width", 640, 8192}, "Window width")->default_val(1600);
  add_integer_option(*cmd, "--height", args->height, {"height", 480, 8192}, "Window height")->default_val(1000);
  cmd->add_flag("!--forget-layout", args->keep_layout,
                "Start from the default layout and do not save it (it lives in ~/.config/dwatch/view.ini)");
  cmd->callback([&run, args] { run = [args] { return view_main(*args); }; });
}

}  // namespace dw::app
