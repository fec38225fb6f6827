// `dwatch why TRACE M VAR T [--depth D] [--narrow]` (docs/files.md, docs/design.md §7b): the causal
// history of a value from a trace recorded with its messages ("recv"), a run's or real robots'
// log, answered as the session's `why` answers it (one JSON line).
#include <iostream>

#include "app/cli/commands.h"
#include "sim/trace_history.h"
#include "sim/why.h"

namespace dw::app {
namespace {

struct WhyArgs {
  std::string trace, variable;
  int64_t module = 0, t = 0;
  int depth = 3;
  bool narrow = false;
};

int why_from_trace(const WhyArgs& args) {
  auto read = sim::read_trace(args.trace);
  if (auto* errors = std::get_if<std::vector<sim::TraceError>>(&read)) {
    for (const sim::TraceError& e : *errors) std::cerr << e.format() << "\n";
    return 2;
  }
  const sim::Trace& trace = std::get<sim::Trace>(read);
  const auto cone =
      sim::why_in_trace(trace, static_cast<uint64_t>(args.module), args.variable, args.t, args.depth, args.narrow);
  if (auto* why = std::get_if<std::string>(&cone)) {
    std::cerr << "dwatch why: " << args.trace << ": error: " << *why << "\n";
    return 2;
  }
  std::cout << sim::cone_json(std::get<sim::Cone>(cone), trace.universe(), {}) << "\n";
  return std::cout ? 0 : 1;
}

}  // namespace

void add_why_command(CLI::App& app, std::function<int()>& run) {
  auto args = std::make_shared<WhyArgs>();
  auto* cmd = app.add_subcommand(
      "why", "The causal history of a value from a trace recorded with its messages (run --record-messages)");
  cmd->add_option("trace", args->trace, "Trace file (JSON Lines, wptrace v1, with \"recv\")")->required();
  cmd->add_option("module", args->module, "Module id M")->required()->check(CLI::NonNegativeNumber);
  cmd->add_option("var", args->variable, "Variable VAR")->required();
  cmd->add_option("t", args->t, "Step T")->required()->check(CLI::Range(int64_t{0}, sim::Trace::kMaxStep));
  cmd->add_option("--depth", args->depth, "Steps back from the value's origin (default 3)")
      ->check(CLI::Range(0, 64))
      ->default_val(3);
  cmd->add_flag("--narrow", args->narrow, "Keep only the events that changed a variable or sent a new message");
  cmd->callback([&run, args] { run = [args] { return why_from_trace(*args); }; });
}

}  // namespace dw::app
