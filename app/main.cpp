// dwatch: a testbed for modular-robot ensembles with distributed watchpoints built in.
#include <cstdlib>
#include <exception>
#include <iostream>
#include <optional>
#include <string>

#include "app/commands.h"
#include "app/terminal_filter.h"
#ifdef DWATCH_MPI
#include "dist/mpi_exchange.h"
#endif

int main(int argc, char** argv) {
  // Before any thread starts (Open MPI's included): signals are taken by one thread of its own.
  // `bench` starts child processes, which would inherit the blocked signals: it keeps the
  // default, ending at once, and writes nothing a signal could leave half done.
  const dw::app::TerminalOutput terminal;  // no control byte from an input reaches a terminal raw
  std::optional<dw::app::Interrupts> interrupts;
  if (argc < 2 || std::string(argv[1]) != "bench") interrupts.emplace();
  dw::app::Interrupts* watcher = interrupts ? &*interrupts : nullptr;
  // Started by mpirun as one of several ranks (docs/design.md §12): only `run` runs over ranks.
  const char* world_size = std::getenv("OMPI_COMM_WORLD_SIZE");
  const bool several = world_size != nullptr && std::atoi(world_size) > 1;
#ifdef DWATCH_MPI
  dw::dist::MpiProcess mpi(argc, argv);
  dw::sim::RankExchange* ranks = mpi.ranks();
#else
  dw::sim::RankExchange* ranks = nullptr;
  if (several) {
    std::cerr << "dwatch: error: started by mpirun as one of " << world_size
              << " ranks, but this dwatch was built without MPI (libopenmpi-dev; scripts/install-deps.sh)\n";
    return 2;
  }
#endif
  if (several && (argc < 2 || std::string(argv[1]) != "run")) {
    if (ranks == nullptr || ranks->rank() == 0)
      std::cerr << "dwatch: error: only 'dwatch run' runs over several ranks (mpirun -np N dwatch run SCENARIO)\n";
    return 2;
  }
  CLI::App app{"dwatch: distributed watchpoints for modular-robot ensembles"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "dwatch " DWATCH_VERSION);
  std::function<int()> run;
  dw::app::add_run_command(app, run, ranks, watcher);
  dw::app::add_check_command(app, run);
  dw::app::add_replay_command(app, run);
  dw::app::add_render_command(app, run, watcher);
  dw::app::add_session_command(app, run, watcher);
  dw::app::add_view_command(app, run);
  dw::app::add_bench_command(app, run);
  // A word where a command belongs that is none of them: say so, and name the real ones.
  if (argc > 1 && argv[1][0] != '-' &&
      app.get_subcommands([&](CLI::App* c) { return c->get_name() == argv[1]; }).empty()) {
    std::string names;
    for (const CLI::App* c : app.get_subcommands([](CLI::App*) { return true; }))
      names += (names.empty() ? "" : ", ") + c->get_name();
    std::cerr << "dwatch: error: unknown command '" << argv[1] << "' (the commands: " << names
              << "; dwatch --help says more)\n";
    return 2;
  }
  // Words a command does not take are kept (allow_extras) and named here in the order given, an
  // option as unknown: CLI11's own message lists them backwards ("not expected: f --scriptt").
  for (CLI::App* c : app.get_subcommands([](CLI::App*) { return true; })) c->allow_extras();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  for (const CLI::App* c : app.get_subcommands()) {
    const std::vector<std::string> extra = c->remaining();
    if (extra.empty()) continue;
    const std::string& word = extra.front();
    std::cerr << "dwatch: error: " << (word.size() > 1 && word[0] == '-' ? "unknown option '" : "unexpected argument '")
              << word << "' for 'dwatch " << c->get_name() << "' (dwatch " << c->get_name()
              << " --help lists what it takes)\n";
    return 2;
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
