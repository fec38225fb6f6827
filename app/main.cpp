// dwatch: a testbed for modular-robot ensembles with distributed watchpoints built in.
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <system_error>

#include "app/cli/commands.h"
#include "app/cli/terminal_filter.h"
#include "bench/bench_command.h"
#include "shell/interrupts.h"
#ifdef DWATCH_MPI
#include "dist/mpi_exchange.h"
#endif

namespace {

// When a command's word is missing, the likely cause: the option given last took it as its own
// value (`run --record S`: S became the trace's file, and no scenario is left). Names the option
// and the word, or returns "".
std::string taken_by_last_option(const CLI::App& app, int argc, char** argv) {
  if (argc < 3) return "";
  const std::string last = argv[argc - 1], option = argv[argc - 2];
  if (option.size() < 2 || option[0] != '-' || last.empty() || last[0] == '-') return "";
  for (const CLI::App* command : app.get_subcommands()) {
    for (const CLI::Option* o : command->get_options()) {
      if (o->get_expected_min() < 1 || !o->check_name(option)) continue;
      return " ('" + option + "' took '" + last +
             "' as its value: give it one of its own, or put the option after the " + "command's own words)";
    }
  }
  return "";
}

// "NAME " of the command argv names, or "" (the mistake was before it): for "dwatch NAME --help".
std::string command_named(const CLI::App& app, int argc, char** argv) {
  for (const CLI::App* c : app.get_subcommands([](const CLI::App*) { return true; }))
    if (argc > 1 && c->get_name() == argv[1]) return c->get_name() + " ";
  return "";
}

// A bench's rows run in child processes that end with it (bench/bench_child.h): a signal ends the
// bench at once, saying so, with 128 + the signal.
void end_bench_at_a_signal() {
  struct sigaction action {};
  action.sa_handler = [](int signal) {  // what it calls is async-signal-safe
    const char* what = dw::shell::Interrupts::name(signal);
    const char* rest = "): stopping at once, with the rows under way; a file not yet complete is not written\n";
    const ssize_t a = ::write(STDERR_FILENO, "dwatch bench: interrupted (", 27);
    const ssize_t b = ::write(STDERR_FILENO, what, std::strlen(what));
    const ssize_t c = ::write(STDERR_FILENO, rest, std::strlen(rest));
    (void)(a + b + c);
    ::_exit(dw::shell::Interrupts::exit_code(signal));
  };
  for (const int s : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(s, &action, nullptr);
}

// Parses the command line into `app`. The exit code when it is refused (with the mistake on
// stderr) or answered (--help, --version); nothing when a command is to run.
std::optional<int> refused_or_answered(CLI::App& app, int argc, char** argv) {
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
  } catch (const CLI::RequiredError& e) {
    std::cerr << "dwatch: error: " << e.what() << taken_by_last_option(app, argc, argv) << "\n";
    return 2;
  } catch (const CLI::ArgumentMismatch& e) {
    // An option given twice, or without its value, or with too many or too few (X,Y,Z).
    const std::string what = e.what(), option = what.substr(0, what.find(':'));
    int given = 0;
    for (int i = 1; i < argc; ++i)
      given += std::string(argv[i]) == option || std::string(argv[i]).rfind(option + "=", 0) == 0;
    std::cerr << "dwatch: error: "
              << (given > 1 ? option + ": given more than once (give it once)"
                  : what.find(" missing") != std::string::npos
                      ? what + " (the option takes a value and was given none)"
                      : what + " (dwatch " + command_named(app, argc, argv) + "--help lists what it takes)")
              << "\n";
    return 2;
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    // CLI11's own words ("--steps: 'steps' must be between 0 and 10000000, not -1"), said the way
    // dwatch says every mistake, with where to look rather than CLI11's "Run with --help".
    std::cerr << "dwatch: error: " << e.what() << " (dwatch " << command_named(app, argc, argv)
              << "--help lists what it takes)\n";
    return 2;
  }
  // An empty word where an option or a command wants a value names no file, variable or text:
  // `--matches ''` was taken as no --matches at all, and wrote nothing.
  for (const CLI::App* c : app.get_subcommands())
    for (const CLI::Option* o : c->get_options([](const CLI::Option* o) { return o->get_expected_min() > 0; }))
      for (const std::string& value : o->results())
        if (value.empty()) {
          std::cerr << "dwatch: error: " << o->get_name() << ": the value is empty\n";
          return 2;
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
  return std::nullopt;
}

// `code`, or 1 when what was printed on standard output could not be written: what a command or
// --help prints is its answer, and one that could not be written (a full disk, a closed pipe:
// SIGPIPE is ignored, see main) is not a success.
int with_output_written(int code) {
  errno = 0;
  std::cout.flush();
  if (std::cout) return code;
  std::cerr << "dwatch: error: writing standard output failed"
            << (errno ? std::string(": ") + std::strerror(errno) : "") << "\n";
  return code == 0 ? 1 : code;
}

// Runs the parsed command: its exit code, or 1 when what it printed could not be written or it
// failed in a way no command reports itself (memory, the system's limits, an internal error).
int carry_out(const std::function<int()>& run) {
  try {
    return with_output_written(run());
  } catch (const std::bad_alloc&) {
    std::cerr << "dwatch: error: out of memory\n";
    return 1;
  } catch (const std::filesystem::filesystem_error& e) {  // a system_error too, but dwatch's mistake
    std::cerr << "dwatch: internal error: " << e.what() << "\n";
    return 1;
  } catch (const std::system_error& e) {
    // The operating system refused a thread or a lock: the machine's limits, not a mistake.
    std::cerr << "dwatch: error: the system refused what dwatch asked for: " << e.what()
              << " (too many --threads for this machine's limits?)\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "dwatch: internal error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  // A closed pipe (`dwatch run s.toml --matches - | head -1`) is a failed write, said and exit 1,
  // not a silent end by SIGPIPE (141): every write to standard output is checked.
  std::signal(SIGPIPE, SIG_IGN);
  // Before any thread starts (Open MPI's included): signals are taken by one thread of its own.
  // `bench` starts child processes, which would inherit the blocked signals: it keeps the
  // default, ending at once, and writes nothing a signal could leave half done.
  const dw::app::TerminalOutput terminal;  // no control byte from an input reaches a terminal raw
  std::optional<dw::shell::Interrupts> interrupts;
  try {
    if (argc < 2 || std::string(argv[1]) != "bench") interrupts.emplace();
    else end_bench_at_a_signal();
  } catch (const std::system_error& e) {  // the thread that takes the signals, refused (`ulimit -u`)
    std::cerr << "dwatch: error: the system refused what dwatch asked for: " << e.what() << "\n";
    return 1;
  }
  dw::shell::Interrupts* watcher = interrupts ? &*interrupts : nullptr;
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
  dw::bench::add_bench_command(app, run, dw::app::bench_view);
  dw::app::add_why_command(app, run);
  if (const std::optional<int> code = refused_or_answered(app, argc, argv)) return with_output_written(*code);
  return carry_out(run);
}
