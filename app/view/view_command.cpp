// `dwatch view SCENARIO [--script FILE]`: the debugger window (docs/design.md §6, §7a). Without a script
// it is the interactive window until closed; with one, the script drives the real window and
// each line is answered with one JSON line, as `dwatch session` answers.
#include <iostream>
#include <memory>

#include "app/cli/commands.h"
#include "app/view/debugger.h"
#include "shell/integer_option.h"
#include "shell/options.h"
#include "sim/read_file.h"

namespace dw::app {
namespace {

struct ViewArgs {
  shell::SessionSource source;
  std::string script;
  int width = 1600, height = 1000;
  bool keep_layout = true;
};

int view_main(const ViewArgs& args) {
  std::optional<scenarios::Scenario> loaded = shell::load_session_scenario(args.source);
  if (!loaded) return 2;
  scenarios::Scenario& scenario = *loaded;
  std::optional<watch::SourceText> script;
  if (!args.script.empty()) {
    std::string error;
    auto text = sim::read_file(args.script, &error);
    if (!text) {
      std::cerr << args.script << ": error: " << error << " (the script)\n";
      return 2;
    }
    script.emplace(args.script, std::move(*text));
    scenario.inputs.push_back(args.script);  // what `record`, `render` or `screenshot` must not overwrite
  }
  auto window = view::GlfwWindow::create(args.width, args.height, "dwatch view  " + scenario.name);
  if (auto* error = std::get_if<std::string>(&window)) {
    std::cerr << "dwatch view: error: " << *error << "\n";
    return 1;
  }
  sim::Session session(*scenario.model, *scenario.world, shell::session_options(scenario, args.source));
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
  shell::add_session_source(*cmd, args->source);
  cmd->add_option(
      "--script", args->script,
      "Drive the window with commands: the session's, plus click M | click match ROW | click timeline T, "
      "key NAME, wait N, press BUTTON, type FIELD TEXT, screenshot FILE, screencast FILE | stop, panel NAME");
  shell::add_integer_option(*cmd, "--width", args->width, {"width", 640, 8192}, "Window width")->default_val(1600);
  shell::add_integer_option(*cmd, "--height", args->height, {"height", 480, 8192}, "Window height")->default_val(1000);
  cmd->add_flag("!--forget-layout", args->keep_layout,
                "Start from the default layout and do not save it (it lives in ~/.config/dwatch/view.ini)");
  cmd->callback([&run, args] { run = [args] { return view_main(*args); }; });
}

}  // namespace dw::app
