// `dwatch session SCENARIO [--script FILE|-|--protocol]`: the debugger without a window (docs/design.md §7a). A
// script is checked whole before anything runs (a mistake is bad input, exit 2); then each
// command is carried out and answered with one JSON object a line, and a command that fails
// stops the script (exit 1, naming its line). On a terminal, without a script, it is a prompt.
#include <sys/stat.h>
#include <unistd.h>
// clang-format off: editline's header needs <cstdio> first
#include <editline/readline.h>
#include <cstdio>
// clang-format on

#include <iostream>
#include <memory>

#include "app/cli/commands.h"
#include "shell/integer_option.h"
#include "shell/options.h"
#include "shell/output_files.h"
#include "shell/protocol.h"
#include "shell/shell.h"
#include "shell/utf8_text.h"
#include "sim/read_file.h"
#include "watch/diagnostic.h"

namespace dw::app {
namespace {

struct SessionArgs {
  shell::SessionSource source;
  std::string script;
  bool protocol = false;
};

// A line that is not UTF-8 text is refused before it is parsed, at its first byte that is not: it
// would name a file nobody can type, and reach the answers.
std::optional<watch::Diagnostic> not_utf8(const std::string& text, size_t begin, size_t end) {
  const auto at = watch::first_non_utf8(std::string_view(text).substr(begin, end - begin));
  if (!at) return std::nullopt;
  const auto byte = static_cast<uint32_t>(begin + *at);
  return watch::Diagnostic{{byte, byte + 1},
                           "a byte that is not UTF-8 text: names, files and watchpoints are read as UTF-8"};
}

// Carries one command out; a signal meanwhile stops it between steps (Interrupts), which the
// second of the pair says.
std::pair<std::variant<nlohmann::ordered_json, std::string>, std::optional<int>> execute(
    shell::Shell& shell, const shell::Command& command, shell::Interrupts* interrupts) {
  if (!interrupts) return {shell.execute(command), std::nullopt};
  shell::Interrupts::Stoppable stoppable(*interrupts);
  auto answer = shell.execute(command, {.stop = stoppable.token()});
  return {std::move(answer), stoppable.signal()};
}

// Every line checked first; then carried out in order. A signal stops the script at the command
// under way.
int run_script(shell::Shell& shell, const watch::SourceText& source, shell::Interrupts* interrupts) {
  std::vector<shell::Command> commands;
  std::string mistakes;
  const std::string& text = source.text();
  uint32_t line = 1;
  for (size_t begin = 0; begin < text.size(); ++line) {
    const size_t newline = text.find('\n', begin);
    const size_t end = newline == std::string::npos ? text.size() : newline;
    if (const auto mistake = not_utf8(text, begin, end)) {
      mistakes += watch::format_diagnostics(source, {*mistake});
    } else {
      auto parsed = shell.parse(source, static_cast<uint32_t>(begin), line);
      if (auto* ds = std::get_if<std::vector<watch::Diagnostic>>(&parsed))
        mistakes += watch::format_diagnostics(source, *ds);
      else if (auto& c = std::get<std::optional<shell::Command>>(parsed)) commands.push_back(std::move(*c));
    }
    begin = end == text.size() ? end : end + 1;
  }
  if (!mistakes.empty()) {
    std::cerr << mistakes;
    return 2;
  }
  for (const shell::Command& c : commands) {
    auto [answer, signal] = execute(shell, c, interrupts);
    if (signal) {
      std::cout.flush();
      std::cerr << source.name() << ":" << c.line << ": interrupted (" << shell::Interrupts::name(*signal)
                << "): the command stopped where it had got to and the script stops here\n";
      return shell::Interrupts::exit_code(*signal);
    }
    if (auto* error = std::get_if<std::string>(&answer)) {
      std::cout.flush();
      std::cerr << source.name() << ":" << c.line << ": error: " << shell::replace_invalid_utf8(*error)
                << " (the script stops here)\n";
      return 1;
    }
    std::cout << shell::answer_line(std::get<nlohmann::ordered_json>(answer)) << "\n" << std::flush;
    if (!std::cout) return 1;  // no answer reaches anyone any more; the caller says why
  }
  return 0;
}

// A prompt with line editing and history (libedit); mistakes and failures are reported and the
// prompt goes on. Ctrl-C stops the command under way; at the prompt it ends the session.
int run_prompt(shell::Shell& shell, shell::Interrupts* interrupts) {
  std::cerr << "dwatch session: 'help' lists the commands, Ctrl-C stops one, Ctrl-D leaves\n";
  while (char* raw = readline("dwatch> ")) {
    const std::string line(raw);
    std::free(raw);
    if (line.find_first_not_of(" \t") != std::string::npos) add_history(line.c_str());
    const watch::SourceText source("<input>", line);
    if (const auto mistake = not_utf8(line, 0, line.size())) {
      std::cerr << watch::format_diagnostics(source, {*mistake});
      continue;
    }
    auto parsed = shell.parse(source, 0, 1);
    if (auto* ds = std::get_if<std::vector<watch::Diagnostic>>(&parsed)) {
      std::cerr << watch::format_diagnostics(source, *ds);
      continue;
    }
    const auto& command = std::get<std::optional<shell::Command>>(parsed);
    if (!command) continue;
    auto [answer, signal] = execute(shell, *command, interrupts);
    if (signal)
      std::cerr << "interrupted (" << shell::Interrupts::name(*signal)
                << "): the command stopped where it had got to\n";
    else if (auto* error = std::get_if<std::string>(&answer))
      std::cerr << "error: " << shell::replace_invalid_utf8(*error) << "\n";
    else std::cout << shell::answer_line(std::get<nlohmann::ordered_json>(answer)) << "\n" << std::flush;
    if (!std::cout) return 1;
  }
  return 0;
}

int session_main(const SessionArgs& args, shell::Interrupts* interrupts) {
  std::optional<scenarios::Scenario> loaded = shell::load_session_scenario(args.source);
  if (!loaded) return 2;
  scenarios::Scenario& scenario = *loaded;
  std::optional<watch::SourceText> script;
  // A script from a file, or piped in (`--script -`, or no terminal), unless it is the protocol.
  const bool piped = !args.protocol && (args.script == "-" || (args.script.empty() && !isatty(STDIN_FILENO)));
  if (!args.script.empty() || piped) {
    std::string error;
    auto text = piped ? sim::read_stream(STDIN_FILENO, "standard input", &error) : sim::read_file(args.script, &error);
    if (!text) {
      std::cerr << (piped ? "<stdin>" : args.script) << ": error: " << error << " (the script)\n";
      return 2;
    }
    script.emplace(piped ? "<stdin>" : args.script, std::move(*text));
    if (!piped) scenario.inputs.push_back(args.script);
  }
  // What `record`, `render` and `save` must not overwrite: the script, also when it is a file
  // piped in or the protocol's requests; and the answers, wherever standard output goes.
  struct stat in {};
  if ((piped || args.protocol) && fstat(STDIN_FILENO, &in) == 0 && S_ISREG(in.st_mode))
    scenario.inputs.push_back("/dev/stdin");
  scenario.inputs.push_back(std::string(shell::kStandardOutput));
  sim::Session session(*scenario.model, *scenario.world, shell::session_options(scenario, args.source));
  shell::Shell shell(scenario, session);
  if (args.protocol) return shell::run_protocol(shell, STDIN_FILENO, std::cout, interrupts);
  return script ? run_script(shell, *script, interrupts) : run_prompt(shell, interrupts);
}

}  // namespace

void add_session_command(CLI::App& app, std::function<int()>& run, shell::Interrupts* interrupts) {
  auto* cmd = app.add_subcommand("session", "The debugger without a window: commands from a script or a prompt");
  auto args = std::make_shared<SessionArgs>();
  shell::add_session_source(*cmd, args->source);
  auto* script = cmd->add_option("--script", args->script, "Commands to carry out, one a line (- for standard input)");
  cmd->add_flag("--protocol", args->protocol,
                "Read requests as they come on standard input and answer each at once, one JSON line each, "
                "with ids, progress and 'cancel' (docs/session.md: the protocol)")
      ->excludes(script);
  cmd->footer("Commands:\n  " + [] {
    std::string all;
    for (const std::string& line : shell::command_help()) all += (all.empty() ? "" : "\n  ") + line;
    return all;
  }());
  cmd->callback([&run, args, interrupts] { run = [args, interrupts] { return session_main(*args, interrupts); }; });
}

}  // namespace dw::app
