// `dwatch why TRACE M VAR T [--depth D] [--narrow]` (docs/files.md, docs/design.md §7b): the causal
// history of a value from a trace recorded with its messages ("recv"), a run's or real robots'
// log, answered as the session's `why` answers it (one JSON line).
#include <algorithm>
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
  const auto fail = [&](const std::string& why) {
    std::cerr << "dwatch why: " << args.trace << ": error: " << why << "\n";
    return 2;
  };
  if (!trace.has_messages())
    return fail(
        "the trace says nothing of messages (no line has \"recv\": record it with `dwatch run --record "
        "--record-messages`)");
  const watch::Universe& universe = trace.universe();
  uint32_t m = 0;
  while (m < universe.module_count() && universe.id(m) != static_cast<uint64_t>(args.module)) ++m;
  if (m == universe.module_count()) return fail("no module " + std::to_string(args.module) + " in the trace");
  const auto var = std::find(universe.variables.begin(), universe.variables.end(), args.variable);
  if (var == universe.variables.end()) return fail("no variable '" + args.variable + "' in the trace");
  if (args.t >= trace.step_count())
    return fail("step " + std::to_string(args.t) + " is past the trace's last, " +
                std::to_string(trace.step_count() - 1));
  if (!trace.line_of(args.t, m))
    return fail("module " + std::to_string(args.module) + " has no line at step " + std::to_string(args.t));
  const auto column = static_cast<uint32_t>(var - universe.variables.begin());
  const sim::ValueAsked value{m, static_cast<int>(column), args.t, sim::trace_origin(trace, m, column, args.t)};
  auto window = sim::trace_window(trace, sim::window_start({&value, 1}, args.depth), value.origin);
  if (auto* why = std::get_if<std::string>(&window)) return fail(*why);
  const sim::Cone cone = sim::cone_of(std::get<sim::CausalHistory>(window), {&value, 1}, args.depth, args.narrow);
  std::cout << sim::cone_json(cone, universe, {}) << "\n";
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
