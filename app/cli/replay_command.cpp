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

#include <cmath>
#include <cstdlib>

#include "app/cli/commands.h"
#include "app/cli/detector_stats.h"
#include "app/cli/watch_args.h"
#include "shell/detector_flags.h"
#include "shell/integer_option.h"
#include "shell/output_files.h"
#include "sim/match_log.h"
#include "sim/replay.h"
#include "sim/trace.h"
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

int replay(const ReplayArgs& args) {
  std::vector<std::string> inputs{args.trace};
  std::vector<sim::HostedWatchpoint> replayed;
  if (!args.watches.empty()) {
    auto loaded = load_watchpoints(args.watches, &inputs);
    if (auto* errors = std::get_if<std::string>(&loaded)) {
      std::cerr << *errors;
      return 2;
    }
    const watch::Algorithm algorithm = args.detector.algorithm();
    const watch::DetectorOptions options = args.detector.options();
    if (const std::string why = watch::unsupported(algorithm, options); !why.empty()) {
      std::cerr << "dwatch: error: " << why << "\n";
      return 2;
    }
    for (watch::Watchpoint& w : std::get<std::vector<watch::Watchpoint>>(loaded))
      replayed.push_back({std::move(w), algorithm, sim::MatchAction::Log, options});
  }

  // Output files are opened before the trace is read, so that a bad path costs nothing.
  const shell::NamedFile matches_file{"--matches", args.matches_path}, stats_file{"--stats", args.stats_path};
  std::unique_ptr<sim::OutputFile> matches_out, stats_out;
  if (!shell::check_distinct_files(inputs, {matches_file, stats_file}) ||
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
  const double parse_seconds = seconds_since(parse_start);
  if (std::string why = sim::replay_work_problem(trace, uint64_t(args.max_module_steps)); !why.empty()) {
    std::cerr << args.trace << ": error: " << why << " (--max-module-steps sets the limit)\n";
    return 2;
  }
  if (args.watches.empty()) {
    auto from_header = header_watches(trace, args.trace, args.detector);
    if (!from_header) return 2;
    replayed = std::move(*from_header);
  }
  std::vector<watch::Watchpoint> watches;
  for (const sim::HostedWatchpoint& r : replayed) watches.push_back(r.watchpoint);
  const watch::Algorithm algorithm = replayed.front().algorithm;
  const watch::DetectorOptions options = replayed.front().options;
  const bool one_reading = std::all_of(replayed.begin(), replayed.end(), [&](const sim::HostedWatchpoint& r) {
    return r.algorithm == algorithm &&
           watch::group_shape(r.algorithm, r.options) == watch::group_shape(algorithm, options) &&
           watch::simultaneous(r.algorithm, r.options) == watch::simultaneous(algorithm, options);
  });

  // Frames hold only what the watchpoints read. A variable no line has would read as unknown
  // everywhere, so its watchpoint can never match: said where it is read, and the replay goes on.
  const std::vector<std::string> read_vars = sim::read_variables(replayed);
  for (const watch::Watchpoint& w : watches)
    for (const std::string& v : w.program.variables) {
      const auto& known = trace.universe().variables;
      if (std::find(known.begin(), known.end(), v) == known.end())
        std::cerr << watch::format_diagnostic(
            *w.source,
            {watch::first_use(w.ast, v), "watchpoint \"" + w.name + "\" reads '" + v + "', which no line of " +
                                             args.trace + " has: it can never match"},
            "warning");
    }
  auto made = sim::FrameReader::make(
      trace, read_vars, args.max_frame_gib > 0 ? args.max_frame_gib * (1u << 30) : sim::default_frame_budget());
  if (auto* why = std::get_if<std::string>(&made)) {
    std::cerr << args.trace << ": error: " << *why << "\n";
    return 1;
  }
  sim::FrameReader& frames = std::get<sim::FrameReader>(made);
  std::vector<sim::MatchLog::WatchInfo> infos;
  for (const watch::Watchpoint& w : watches) {
    infos.push_back(sim::MatchLog::info(w));
    // docs/design.md §4b: a trace cannot change, and already holds what the run's actions did.
    if (!w.program.actions.empty())
      std::cerr << "dwatch: watchpoint '" << w.name
                << "' has actions: replay reports its matches and what they would do, and performs none\n";
  }
  sim::MatchLog log(std::move(infos), out, std::max<size_t>(args.print, 1));

  std::vector<uint64_t> counted(watches.size(), 0);  // of count-only watchpoints
  const auto matches_of = [&](size_t i) {
    return replayed[i].action == sim::MatchAction::Count ? counted[i] : log.count(i);
  };
  std::vector<watch::MatchSink> logged;
  for (size_t i = 0; i < watches.size(); ++i) logged.push_back(log.sink(i));

  // The run's own watchpoints find what the run found: a run a pause stopped left its last steps
  // undecided. Other watchpoints decide them, as at the end of any trace.
  const bool drain = !args.watches.empty() || !trace.paused();
  const auto detect_start = std::chrono::steady_clock::now();
  const std::vector<watch::DetectorStats> stats = sim::replay(
      frames, trace.step_count(), replayed,
      [&](size_t i, int64_t, int64_t t, std::span<const watch::ModuleId> ids, std::span<const watch::Value> actions) {
        if (replayed[i].action == sim::MatchAction::Count) counted[i] += ids.size() / watches[i].program.slot_count();
        else logged[i](t, ids, actions);
      },
      [&](int64_t t) { log.release(t); }, drain);
  for (size_t i = 0; i < watches.size(); ++i)
    if (replayed[i].action == sim::MatchAction::Count) log.write_counted(watches[i].name, counted[i]);  // as run
  const double detect_seconds = seconds_since(detect_start);

  // The summary goes to stdout unless the matches do.
  std::ostream& summary = args.matches_path == "-" || args.stats_path == "-" ? std::cerr : std::cout;
  summary << "replay " << args.trace << ": " << trace.line_count() << " lines, " << trace.step_count() << " steps, "
          << trace.modules_with_lines() << " modules";
  if (const uint32_t only_named = trace.universe().module_count() - trace.modules_with_lines())
    summary << " (and " << only_named << " named only as neighbours)";
  if (one_reading)
    summary << "; " << reading_text(algorithm, options, watches.front().program.slot_count()) << " detector\n";
  else summary << "; each watchpoint read as the run that recorded the trace read it\n";
  if (!drain)
    summary << "  the run stopped at " << trace.paused()->watch << "'s pause (step " << trace.paused()->t
            << "): its last steps stay undecided, as the run left them\n";
  bool stopped = false;
  uint64_t total = 0;
  for (size_t i = 0; i < watches.size(); ++i) {
    const watch::DetectorStats& st = stats[i];
    total += matches_of(i);
    summary << "  " << watches[i].name;
    if (!one_reading)
      summary << " [" << reading_text(replayed[i].algorithm, replayed[i].options, watches[i].program.slot_count())
              << "]";
    summary << ": " << matches_of(i) << " match" << (matches_of(i) == 1 ? "" : "es") << "\n";
    print_detector_stats(summary, st);
    if (out == nullptr) {
      const auto& slots = watches[i].program.slot_names;
      for (const sim::MatchLog::Kept& k : log.kept(i)) {
        if (&k - log.kept(i).data() >= static_cast<ptrdiff_t>(args.print)) break;
        summary << "    t=" << k.t;
        for (size_t s = 0; s < slots.size(); ++s) summary << " " << slots[s] << "=" << k.ids[s];
        summary << "\n";
      }
      if (log.count(i) > args.print && args.print > 0)
        summary << "    ... " << (log.count(i) - args.print) << " more (--matches FILE writes them all)\n";
    }
    if (st.stopped) {
      stopped = true;
      std::cerr << "dwatch: " << watches[i].name << ": stopped: " << st.stop_reason
                << "; the matches found before are kept (--max-live sets the budget)\n";
    }
  }
  summary << std::fixed << std::setprecision(3) << "  time: reading " << parse_seconds << " s, detecting "
          << detect_seconds << " s\n";

  if (stats_out) {
    nlohmann::ordered_json j;
    j["matches"] = total;
    j["algorithm"] = watch::algorithm_name(algorithm);
    j["shape"] = watch::shape_name(watch::group_shape(algorithm, options));
    if (algorithm == watch::Algorithm::Distributed)
      j["states"] = watch::states_name(options.states.value_or(watch::States::Consistent));
    j["trace"] = {{"path", args.trace},
                  {"lines", trace.line_count()},
                  {"steps", trace.step_count()},
                  {"modules", trace.modules_with_lines()},
                  {"modules_named_only_as_neighbours", trace.universe().module_count() - trace.modules_with_lines()}};
    j["seconds"] = {{"reading", parse_seconds}, {"detecting", detect_seconds}};
    j["watches"] = nlohmann::json::array();
    for (size_t i = 0; i < watches.size(); ++i) j["watches"].push_back(stats_json(watches[i], stats[i], matches_of(i)));
    stats_out->stream() << j.dump(1) << "\n";
  }
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
