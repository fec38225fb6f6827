// dwatch: a testbed for modular-robot ensembles with distributed watchpoints built in.
#include <exception>
#include <iostream>

#include "app/commands.h"

int main(int argc, char** argv) {
  CLI::App app{"dwatch: distributed watchpoints for modular-robot ensembles"};
  app.require_subcommand(1);
  std::function<int()> run;
  dw::app::add_run_command(app, run);
  dw::app::add_check_command(app, run);
  dw::app::add_replay_command(app, run);
  dw::app::add_render_command(app, run);
  dw::app::add_bench_command(app, run);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    return run();
  } catch (const std::bad_alloc&) {
    std::cerr << "dwatch: error: out of memory\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "dwatch: internal error: " << e.what() << "\n";
    return 1;
  }
}
