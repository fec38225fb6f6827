// `dwatch replay TRACE --watch ...`: run watchpoints over a recorded trace.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>

#include "app/cli/commands.h"
#include "app/cli/run_summary.h"
#include "app/cli/watch_args.h"
#include "shell/detector_flags.h"
#include "shell/integer_option.h"
#include "shell/output_files.h"
#include "sim/replay.h"
#include "sim/run_outputs.h"
#include "watch/watchpoint.h"

namespace dw::app {
namespace {

struct ReplayArgs {
  std::string trace;
  std::vector<std::string> watches;
  std::string matches_path;
  std::string stats_path;
  size_t print = 20;
  double max_frame_gib = 0;      // 0: a quarter of the machine's memory
  int64_t max_module_steps = 0;  // 0: sim::replay_work_problem's default
  shell::DetectorFlags detector;
};

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// The watchpoints given with --watch, with the command line's reading, each match logged;
// nothing, the errors printed, when one does not compile or the reading cannot run.
std::optional<std::vector<sim::HostedWatchpoint>> given_watches(const ReplayArgs& args,
                                                                std::vector<std::string>& inputs) {
  const sim::WatchSpec reading = args.detector.reading();
  auto loaded = load_watchpoints(args.watches, reading, &inputs);
  if (auto* errors = std::get_if<std::string>(&loaded)) {
    std::cerr << *errors;
    return std::nullopt;
  }
  if (const std::string why = watch::unsupported(reading.algorithm, reading.options); !why.empty()) {
    std::cerr << "dwatch: error: " << why << "\n";
    return std::nullopt;
  }
  return std::get<std::vector<sim::HostedWatchpoint>>(std::move(loaded));
}

// The watchpoints the trace's header lists, each with the reading and action the recording run
// gave it (the command line's optimization switches and budget apply; the trace reader refused a
// reading that cannot run); nothing, with the errors printed, when one does not compile or there is none.
std::optional<std::vector<sim::HostedWatchpoint>> header_watches(const sim::Trace& trace, const std::string& path,
                                                                 const shell::DetectorFlags& flags) {
  auto hosted = sim::hosted_watches(trace.watches(), path, flags.options());
  if (auto* errors = std::get_if<std::string>(&hosted)) {
    std::cerr << *errors;
    return std::nullopt;
  }
  auto& out = std::get<std::vector<sim::HostedWatchpoint>>(hosted);
  if (out.empty())
    std::cerr << path << ": error: the trace's header lists no watchpoints (a trace recorded by dwatch run lists "
              << "its scenario's): give them with --watch\n";
  return out.empty() ? std::nullopt : std::optional(std::move(out));
}

// A variable no line has would read as unknown everywhere, so its watchpoint can never match:
// said where it is read, and the replay goes on. So is what a watchpoint's actions would do.
void warn_of(std::span<const sim::HostedWatchpoint> replayed, const sim::Trace& trace, const std::string& path) {
  const auto& known = trace.universe().variables;
  for (const sim::HostedWatchpoint& h : replayed) {
    const watch::Watchpoint& w = h.watchpoint;
    for (const std::string& v : w.program.variables)
      if (std::find(known.begin(), known.end(), v) == known.end())
        std::cerr << watch::format_diagnostic(
            *w.source,
            {watch::first_use(w.ast, v),
             "watchpoint \"" + w.name + "\" reads '" + v + "', which no line of " + path + " has: it can never match"},
            "warning");
  }
}

void warn_of_actions(std::span<const sim::HostedWatchpoint> replayed) {
  // docs/design.md §4b: a trace cannot change, and already holds what the run's actions did.
  for (const sim::HostedWatchpoint& h : replayed)
    if (!h.watchpoint.program.actions.empty())
      std::cerr << "dwatch: watchpoint '" << h.watchpoint.name
                << "' has actions: replay reports its matches and what they would do, and performs none\n";
}

// Whether every watchpoint reads alike (then the summary says the reading once).
bool one_reading(std::span<const sim::HostedWatchpoint> replayed) {
  const sim::HostedWatchpoint& first = replayed.front();
  return std::all_of(replayed.begin(), replayed.end(), [&](const sim::HostedWatchpoint& r) {
    return r.algorithm == first.algorithm &&
           watch::group_shape(r.algorithm, r.options) == watch::group_shape(first.algorithm, first.options) &&
           watch::simultaneous(r.algorithm, r.options) == watch::simultaneous(first.algorithm, first.options);
  });
}

struct Replayed {
  std::vector<sim::HostedWatchpoint> watches;
  std::vector<watch::DetectorStats> stats;
  bool drained = true;
  double parse_seconds = 0, detect_seconds = 0;
};

// The summary: the trace, the reading, each watchpoint's matches and statistics; whether one's
// budget stopped it.
bool print_replay_summary(std::ostream& summary, const ReplayArgs& args, const sim::Trace& trace, const Replayed& r,
                          const sim::RunOutputs& outputs, bool listed_elsewhere) {
  const bool alike = one_reading(r.watches);
  summary << "replay " << args.trace << ": " << trace.line_count() << " lines, " << trace.step_count() << " steps, "
          << trace.modules_with_lines() << " modules";
  if (const uint32_t only_named = trace.universe().module_count() - trace.modules_with_lines())
    summary << " (and " << only_named << " named only as neighbours)";
  const sim::HostedWatchpoint& first = r.watches.front();
  if (alike)
    summary << "; " << reading_text(first.algorithm, first.options, first.watchpoint.program.slot_count())
            << " detector\n";
  else summary << "; each watchpoint read as the run that recorded the trace read it\n";
  if (!r.drained)
    summary << "  the run stopped at " << trace.paused()->watch << "'s pause (step " << trace.paused()->t
            << "): its last steps stay undecided, as the run left them\n";
  bool stopped = false;
  for (uint32_t i = 0; i < r.watches.size(); ++i) {
    const sim::HostedWatchpoint& h = r.watches[i];
    summary << "  " << h.watchpoint.name;
    if (!alike) summary << " [" << reading_text(h.algorithm, h.options, h.watchpoint.program.slot_count()) << "]";
    summary << ": " << outputs.count(i) << " match" << (outputs.count(i) == 1 ? "" : "es") << "\n";
    print_detector_stats(summary, r.stats[i]);
    if (!listed_elsewhere)
      print_first_matches(summary, h.watchpoint.program.slot_names, outputs.listed(i), args.print, [&](size_t m) {
        const sim::MatchLog::Kept& kept = outputs.kept(i)[m];
        return std::pair{kept.t, std::span<const watch::ModuleId>(kept.ids)};
      });
    stopped = say_stopped(std::cerr, h.watchpoint.name, r.stats[i], "--max-live") || stopped;
  }
  summary << std::fixed << std::setprecision(3) << "  time: reading " << r.parse_seconds << " s, detecting "
          << r.detect_seconds << " s\n";
  return stopped;
}

// --stats: the matches, the (first watchpoint's) reading, the trace, the times, each watchpoint's
// statistics.
nlohmann::ordered_json replay_stats_json(const ReplayArgs& args, const sim::Trace& trace, const Replayed& r,
                                         const sim::RunOutputs& outputs) {
  uint64_t total = 0;
  for (uint32_t i = 0; i < r.watches.size(); ++i) total += outputs.count(i);
  const sim::WatchSpec reading = sim::spec_of(r.watches.front());
  nlohmann::ordered_json j;
  j["matches"] = total;
  j["algorithm"] = reading.algorithm_name();
  j["shape"] = reading.shape_name();
  if (reading.distributed()) j["states"] = reading.states_name();
  j["trace"] = {{"path", args.trace},
                {"lines", trace.line_count()},
                {"steps", trace.step_count()},
                {"modules", trace.modules_with_lines()},
                {"modules_named_only_as_neighbours", trace.universe().module_count() - trace.modules_with_lines()}};
  j["seconds"] = {{"reading", r.parse_seconds}, {"detecting", r.detect_seconds}};
  j["watches"] = nlohmann::json::array();
  for (uint32_t i = 0; i < r.watches.size(); ++i)
    j["watches"].push_back(stats_json(sim::spec_of(r.watches[i]), r.stats[i], outputs.count(i)));
  return j;
}

int replay(const ReplayArgs& args) {
  std::vector<std::string> inputs{args.trace};
  Replayed r;
  if (!args.watches.empty()) {
    auto given = given_watches(args, inputs);
    if (!given) return 2;
    r.watches = std::move(*given);
  }

  // Output files are opened before the trace is read, so that a bad path costs nothing.
  const shell::NamedFile matches_file{"--matches", args.matches_path}, stats_file{"--stats", args.stats_path};
  std::unique_ptr<sim::OutputFile> matches_out, stats_out;
  // The summary goes to standard output unless an output does: redirected onto an output's file,
  // it would be lost under the output committed over it.
  if (args.matches_path != "-" && args.stats_path != "-") inputs.emplace_back(shell::kStandardOutput);
  if (!shell::check_distinct_files(inputs, {matches_file, stats_file}, "where the summary goes") ||
      !shell::open_output(matches_file, matches_out) || !shell::open_output(stats_file, stats_out))
    return 2;
  std::ostream* out = shell::stream_of(matches_out);

  const auto parse_start = std::chrono::steady_clock::now();
  auto read = sim::read_trace(args.trace);
  if (auto* errors = std::get_if<std::vector<sim::TraceError>>(&read)) {
    for (const sim::TraceError& e : *errors) std::cerr << e.format() << "\n";
    return 2;
  }
  const sim::Trace& trace = std::get<sim::Trace>(read);
  r.parse_seconds = seconds_since(parse_start);
  if (std::string why = sim::replay_work_problem(trace, uint64_t(args.max_module_steps)); !why.empty()) {
    std::cerr << args.trace << ": error: " << why << " (--max-module-steps sets the limit)\n";
    return 2;
  }
  if (args.watches.empty()) {
    auto from_header = header_watches(trace, args.trace, args.detector);
    if (!from_header) return 2;
    r.watches = std::move(*from_header);
  }

  // Frames hold only what the watchpoints read.
  warn_of(r.watches, trace, args.trace);
  auto made =
      sim::FrameReader::make(trace, sim::read_variables(r.watches),
                             args.max_frame_gib > 0 ? args.max_frame_gib * (1u << 30) : sim::default_frame_budget());
  if (auto* why = std::get_if<std::string>(&made)) {
    std::cerr << args.trace << ": error: " << *why << "\n";
    return 1;
  }
  warn_of_actions(r.watches);
  sim::RunOutputs outputs(r.watches, out, std::max<size_t>(args.print, 1));
  r.drained = sim::RunOutputs::replay_drains(trace, args.watches.empty());
  const auto detect_start = std::chrono::steady_clock::now();
  r.stats = sim::replay(
      std::get<sim::FrameReader>(made), trace.step_count(), r.watches,
      [&](size_t i, int64_t, int64_t t, std::span<const watch::ModuleId> ids, std::span<const watch::Value> actions) {
        outputs.found(uint32_t(i), t, watch::match_rows(ids.size(), r.watches[i].watchpoint.program.slot_count()), ids,
                      actions);
      },
      [&](int64_t t) { outputs.release(t); }, r.drained);
  outputs.finish();  // as run: each count watchpoint's number last
  r.detect_seconds = seconds_since(detect_start);

  // The summary goes to stdout unless the matches do.
  std::ostream& summary = args.matches_path == "-" || args.stats_path == "-" ? std::cerr : std::cout;
  const bool stopped = print_replay_summary(summary, args, trace, r, outputs, out != nullptr);
  if (stats_out) stats_out->stream() << replay_stats_json(args, trace, r, outputs).dump(1) << "\n";
  if (!shell::commit_outputs({matches_out.get(), stats_out.get()})) return 1;
  return stopped ? 1 : 0;
}

}  // namespace

void add_replay_command(CLI::App& app, std::function<int()>& run) {
  auto* cmd = app.add_subcommand("replay", "Run watchpoints over a recorded trace (wptrace v1)");
  auto args = std::make_shared<ReplayArgs>();
  cmd->add_option("trace", args->trace, "Trace file (JSON Lines, wptrace v1)")->required();
  cmd->add_option("--watch,-w", args->watches,
                  "Watchpoint text, @FILE, NAME=TEXT or NAME=@FILE (repeatable; default: the watchpoints the "
                  "trace's header lists, each with its run's reading)");
  cmd->add_option("--matches", args->matches_path, "Write every match as JSON Lines to FILE (- for stdout)");
  cmd->add_option("--stats", args->stats_path, "Write run statistics as JSON to FILE");
  shell::add_integer_option(*cmd, "--print", args->print, {"print", 0, 1'000'000},
                            "Matches to print per watchpoint when --matches is not given")
      ->default_val(20);
  cmd->add_option("--max-frame-memory", args->max_frame_gib,
                  "GiB one dense frame (modules x variables read) may take (default: a quarter of the memory)")
      ->check(CLI::Validator(
          [](const std::string& text) {
            // CLI::Range lets nan through (every comparison with it is false).
            const double v = std::strtod(text.c_str(), nullptr);
            return std::isfinite(v) && v >= 0.001 && v <= 1e6 ? std::string()
                                                              : "must be a number of GiB from 0.001 to 1000000";
          },
          "GiB", "finite GiB"));
  shell::add_integer_option(
      *cmd, "--max-module-steps", args->max_module_steps, {"max-module-steps", 1, std::numeric_limits<int64_t>::max()},
      "Steps x modules the detection may go over (default: 1,000 per line of the trace, at least 10^9)");
  shell::add_detector_flags(*cmd, args->detector);
  cmd->callback([&run, args] { run = [args] { return replay(*args); }; });
}

}  // namespace dw::app
