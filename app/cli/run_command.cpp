// `dwatch run SCENARIO`: run a scenario headless with its watchpoints live (docs/design.md §6).
#include <sys/resource.h>
#include <algorithm>
#include <chrono>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "app/cli/commands.h"
#include "app/cli/detector_stats.h"
#include "app/cli/progress.h"
#include "scenarios/scenario.h"
#include "shell/integer_option.h"
#include "shell/options.h"
#include "shell/output_files.h"
#include "shell/view_image.h"
#include "sim/match_log.h"
#include "sim/session.h"
#include "sim/trace.h"

namespace dw::app {
namespace {

struct RunArgs {
  std::string scenario;
  std::optional<int64_t> steps, seed, threads, history_mb, max_live;
  std::string algorithm, shape, states, partition = "auto";
  std::string record_path, matches_path, stats_path, render_path;
  size_t print = 5;
  bool no_progress = false;
  bool no_memory_check = false;
};

int run_scenario(const RunArgs& args, sim::RankExchange* ranks, shell::Interrupts* interrupts) {
  // The time reported covers the set-up too: loading, the world, the first state.
  const auto started = std::chrono::steady_clock::now();
  // Over several ranks, rank 0 speaks and writes the outputs; every rank runs its part.
  const bool lead = ranks == nullptr || ranks->rank() == 0;
  std::ostream quiet(nullptr);
  std::ostream& errors = lead ? std::cerr : quiet;
  scenarios::ScenarioOverrides overrides;
  if (args.seed) overrides.seed = static_cast<uint64_t>(*args.seed);
  if (!args.algorithm.empty())
    overrides.algorithm =
        args.algorithm == "centralized" ? watch::Algorithm::Centralized : watch::Algorithm::Distributed;
  if (!args.shape.empty()) overrides.shape = watch::parse_shape(args.shape);
  if (!args.states.empty()) overrides.states = watch::parse_states(args.states);
  if (args.max_live) overrides.max_live = static_cast<uint64_t>(*args.max_live);
  overrides.memory_limit = shell::memory_limit_unless(args.no_memory_check);
  auto loaded = scenarios::load_scenario(args.scenario, overrides);
  if (auto* message = std::get_if<std::string>(&loaded)) {
    errors << *message;
    return 2;
  }
  scenarios::Scenario& scenario = std::get<scenarios::Scenario>(loaded);
  const sim::Model& model = *scenario.model;
  const int64_t steps = args.steps.value_or(scenario.steps);
  const unsigned threads = args.threads ? static_cast<unsigned>(*args.threads) : scenario.threads;
  const size_t history_mb = args.history_mb ? static_cast<size_t>(*args.history_mb) : scenario.history_mb;

  if (args.render_path == "-") {
    errors << "dwatch: error: --render needs a file name\n";
    return 2;
  }
  if (ranks) {
    if (const std::string why = sim::why_not_over_ranks(model); !why.empty()) {
      errors << "dwatch: error: " << args.scenario << " cannot run over " << ranks->ranks() << " ranks: " << why
             << "\n";
      return 2;
    }
  }
  const shell::NamedFile record_file{"--record", args.record_path}, matches_file{"--matches", args.matches_path},
      stats_file{"--stats", args.stats_path}, render_file{"--render", args.render_path};
  std::unique_ptr<sim::OutputFile> record_out, matches_out, stats_out, render_out;
  // Only rank 0 opens the outputs; if it cannot, every rank stops.
  if (sim::any_rank(
          ranks,
          lead &&
              !(shell::check_distinct_files(scenario.inputs, {record_file, matches_file, stats_file, render_file}) &&
                shell::open_output(record_file, record_out) && shell::open_output(matches_file, matches_out) &&
                shell::open_output(stats_file, stats_out) && shell::open_output(render_file, render_out))))
    return 2;
  std::ostream *record = shell::stream_of(record_out), *matches = shell::stream_of(matches_out),
               *stats = shell::stream_of(stats_out);
  const bool to_stdout = args.record_path == "-" || args.matches_path == "-" || args.stats_path == "-";

  std::vector<sim::MatchLog::WatchInfo> infos;
  int64_t max_lag = 0;
  for (const sim::HostedWatchpoint& h : model.watches) {
    infos.push_back(sim::MatchLog::info(h.watchpoint));
    max_lag = std::max(max_lag, h.lag());
  }
  sim::MatchLog log(std::move(infos), matches, 1);
  std::vector<watch::MatchSink> sinks;
  for (size_t w = 0; w < model.watches.size(); ++w) sinks.push_back(log.sink(w));
  std::unique_ptr<sim::TraceWriter> recorder;
  if (record)
    recorder =
        std::make_unique<sim::TraceWriter>(*record, model.universe, scenario.events, sim::trace_watches(model.watches));
  const bool recording = !args.record_path.empty();  // on every rank: each gives its part of each frame

  sim::Session run(*scenario.model, *scenario.world,
                   {threads, steps, history_mb << 20, scenario.events, ranks, sim::partition_named(args.partition)});
  ProgressBar progress("run " + scenario.name, steps, lead && !args.no_progress);
  // A signal stops the run between steps, the outputs left uncommitted. Over ranks every rank
  // would have to stop at the same step: a signal ends each at once instead.
  const auto stepping = std::chrono::steady_clock::now();
  std::optional<shell::Interrupts::Stoppable> stoppable;
  sim::Control control;
  if (interrupts && !ranks) {
    stoppable.emplace(*interrupts);
    control.stop = stoppable->token();
  }
  // A signal that stopped the stepping, or came while the outputs were made: nothing is written.
  // Only the commits, together at the end, are not stoppable: a signal then ends the process at
  // once, each output complete or as it was.
  const auto interrupted = [&](const std::string& when) {
    const std::optional<int> signal = stoppable ? stoppable->signal() : std::nullopt;
    stoppable.reset();
    if (!signal) return 0;
    progress.finish();
    errors << "dwatch: run " << args.scenario << " interrupted (" << shell::Interrupts::name(*signal) << ") " << when
           << ": nothing written";
    std::string kept;
    for (const shell::NamedFile& f : {record_file, matches_file, stats_file, render_file})
      if (!f.path.empty() && f.path != "-") kept += (kept.empty() ? "" : ", ") + f.what + " " + f.path;
    if (!kept.empty()) errors << " (" << kept << ": as they were before the run)";
    errors << "\n";
    return shell::Interrupts::exit_code(*signal);
  };
  std::optional<sim::Pause> pause;
  try {
    pause = run.run_until(
        steps,
        [&](const sim::State& state, const sim::StepOutput& out) {
          if (recording) {
            std::vector<int64_t> values = run.whole_values(state);
            const std::shared_ptr<const sim::NeighborGraph> graph = run.whole_graph(out.graph);
            if (recorder) recorder->write(sim::make_frame(model, out.step, values, out.present, graph));
          }
          for (size_t w = 0; w < out.watches.size(); ++w)
            if (!out.watches[w].slots.empty() && model.watches[w].action != sim::MatchAction::Count)
              sinks[w](out.watches[w].t, out.watches[w].slots, out.watches[w].actions);
          log.release(out.step - max_lag);
          progress.update(out.step + 1);
        },
        control);
    if (const int code =
            interrupted("after " + std::to_string(run.latest() + 1) + " of " + std::to_string(steps) + " steps");
        code != 0)
      return code;
    if (interrupts && !ranks) stoppable.emplace(*interrupts);  // while the outputs are made
    // A run a pause stopped says so at its trace's end: replayed, its watchpoints find what it
    // found, leaving its last steps undecided as it did.
    if (pause && recorder) recorder->write_paused({model.watches[pause->watch].watchpoint.name, pause->t});
    // Simultaneous-state watchpoints decide the run's last steps by draining (docs/design.md §4a).
    if (!pause && run.latest() + 1 == steps)
      run.drain(
          [&](uint32_t w, int64_t t, std::span<const watch::ModuleId> ids, std::span<const watch::Value> actions) {
            if (model.watches[w].action != sim::MatchAction::Count) sinks[w](t, ids, actions);
          });
  } catch (const sim::ProgramError& e) {
    progress.finish();
    errors << "dwatch: " << args.scenario << ": error: " << e.what() << "\n";
    return 1;
  }
  log.finish();
  for (uint32_t w = 0; w < model.watches.size(); ++w)
    if (model.watches[w].action == sim::MatchAction::Count)
      log.write_counted(model.watches[w].watchpoint.name, run.match_count(w));
  progress.finish();
  const auto now = std::chrono::steady_clock::now();
  const double seconds = std::chrono::duration<double>(now - started).count();
  const double setup_seconds = std::chrono::duration<double>(stepping - started).count();
  const int64_t ran = run.latest() + 1;

  std::ostream& summary = !lead ? quiet : to_stdout ? std::cerr : std::cout;
  const auto& spec = model.lattice.spec;
  const auto& occupied = model.lattice.occupied;
  const size_t present = static_cast<size_t>(std::count(occupied.begin(), occupied.end(), 1));
  summary << "run " << args.scenario << ": " << present << " modules (" << sim::lattice_name(spec.kind) << " "
          << spec.size[0];
  for (int d = 1; d < sim::lattice_dimensions(spec.kind); ++d) summary << "x" << spec.size[size_t(d)];
  if (present < occupied.size()) summary << ", " << occupied.size() - present << " cells left empty";
  summary << "), " << ran << (ran == 1 ? " step" : " steps") << " of " << steps << ", seed " << model.seed << ", "
          << threads << (threads == 1 ? " thread" : " threads");
  const std::string shared_by(sim::partition_name(run.partition()));
  if (ranks) summary << " on each of " << ranks->ranks() << " ranks (partition: " << shared_by << ")";
  summary << "\n  programs:";
  for (const auto& p : model.programs) summary << " " << p->name();
  summary << "; " << run.head().program_messages << " program messages\n";

  bool stopped = false;
  for (uint32_t w = 0; w < model.watches.size(); ++w) {
    const sim::HostedWatchpoint& h = model.watches[w];
    const uint64_t count = run.match_count(w);
    summary << "  " << h.watchpoint.name << " ["
            << reading_text(h.algorithm, h.options, h.watchpoint.program.slot_count()) << ", "
            << sim::action_name(h.action) << "]: " << count << " match" << (count == 1 ? "" : "es");
    if (pause && pause->watch == w) {
      summary << "; PAUSED at step " << pause->t;
      if (pause->detected != pause->t) summary << " (detected at step " << pause->detected << ")";
      summary << ": " << group_text(h.watchpoint.program.slot_names, pause->group);
      if (pause->matches > 1) summary << " and " << pause->matches - 1 << " more at that step";
    }
    summary << "\n";
    const sim::MatchList& list = run.matches(w);
    if (matches == nullptr) {
      const size_t k = static_cast<size_t>(h.watchpoint.program.slot_count());
      for (size_t i = 0; i < list.size() && i < args.print; ++i)
        summary << "    t=" << list.t[i] << " "
                << group_text(h.watchpoint.program.slot_names, {list.slots.data() + i * k, k}) << "\n";
      if (list.size() > args.print && args.print > 0)
        summary << "    ... " << (list.size() - args.print) << " more (--matches FILE writes them all)\n";
    }
    print_detector_stats(summary, run.stats(w));
    if (!h.watchpoint.program.actions.empty())
      summary << "    actions: " << run.head().watches[w].actions_done << " done, "
              << run.head().watches[w].actions_skipped << " skipped (value unknown, module gone or no such variable)\n";
    if (run.stats(w).stopped) {
      stopped = true;
      errors << "dwatch: " << h.watchpoint.name << ": stopped: " << run.stats(w).stop_reason
             << "; the matches found before are kept (max_live sets the budget)\n";
    }
  }
  // The session stands at the paused match's step (or the last one run): the state shown and
  // hashed is that step's. Counts and statistics are of everything run.
  std::vector<uint64_t> counts;
  std::vector<watch::DetectorStats> totals;
  for (uint32_t w = 0; w < model.watches.size(); ++w) {
    counts.push_back(run.match_count(w));
    totals.push_back(run.stats(w));
  }
  const bool rolled_back = pause && run.current() < run.latest();
  if (rolled_back) summary << "  rolled back to step " << pause->t << ", the paused match's step\n";
  const sim::StateHash hash = run.hash();
  uint64_t between_ranks = run.bytes_to_ranks();
  if (ranks) ranks->sum({&between_ranks, 1});
  // Peak memory: this process's, and over ranks the largest rank's and all ranks' together.
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  uint64_t peak_kib_all = static_cast<uint64_t>(usage.ru_maxrss);
  const uint64_t peak_kib = sim::max_over_ranks(ranks, peak_kib_all);
  if (ranks) ranks->sum({&peak_kib_all, 1});
  // The physics part of the steps: over ranks, the slowest rank's.
  const double physics_seconds = sim::max_over_ranks(ranks, run.world_seconds());
  const double step_seconds = seconds - setup_seconds;
  summary << std::fixed << std::setprecision(3) << "  time: " << seconds << " s (set-up " << setup_seconds
          << " s, steps " << step_seconds << " s";
  if (ran > 0 && model.module_count() > 0)
    summary << std::setprecision(2) << ", " << step_seconds * 1e9 / double(ran) / model.module_count()
            << " ns per module-step";
  summary << ")";
  if (scenario.world->moves() && ran > 0)
    summary << std::setprecision(2) << "\n  physics: " << physics_seconds << " s of the steps, "
            << 1e3 * physics_seconds / double(ran) << " ms a step (bodies, contacts, the graph"
            << (ranks ? "; the slowest rank's)" : ")");
  summary << "\n  state hash: " << sim::hash_text(hash) << "\n";
  if (ranks && ran > 0)
    summary << "  between ranks: " << between_ranks << " bytes, " << between_ranks / uint64_t(ran)
            << " per step (program messages and PatternMatchers)\n";

  if (!args.render_path.empty()) {
    // The view at the paused match's step with its group, or at the last step run.
    const int64_t shown = std::max<int64_t>(0, run.current());
    std::vector<render::SceneGroup> groups;
    if (pause && shown == pause->t) {
      const watch::Watchpoint& w = model.watches[pause->watch].watchpoint;
      groups.push_back({w.name, pause->t, w.program.slot_names, pause->group});
    }
    render::SceneSettings settings = shell::scene_settings(scenario, "");
    settings.title = scenario.name + "  \xC2\xB7  step " + std::to_string(shown);
    sim::State whole = run.state();  // over ranks, the variables of every rank's modules
    whole.values = run.whole_values(whole);
    if (!lead) return stopped ? 1 : 0;
    const render::Scene scene = render::build_scene(model, whole, groups, settings);
    if (shell::camera_refused(scene, 1280, 720)) return 2;
    if (std::string error = shell::write_view(scene, *render_out, 1280, 720); !error.empty()) {
      std::cerr << "dwatch: error: " << error << "\n";
      return 1;
    }
    summary << "  view of step " << shown << " written to " << args.render_path << "\n";
  }

  if (stats) {
    nlohmann::ordered_json j;
    j["scenario"] = args.scenario;
    j["modules"] = present;
    j["steps"] = ran;
    j["seed"] = model.seed;
    j["threads"] = threads;
    j["ranks"] = ranks ? ranks->ranks() : 1;
    if (ranks) j["partition"] = shared_by;
    j["bytes_between_ranks"] = between_ranks;
    j["peak_mib"] = double(peak_kib) / 1024;  // of the largest rank
    j["peak_mib_all_ranks"] = double(peak_kib_all) / 1024;
    j["seconds"] = seconds;
    j["setup_seconds"] = setup_seconds;
    if (scenario.world->moves()) j["physics_seconds"] = physics_seconds;
    j["program_messages"] = run.head().program_messages;
    j["state_hash"] = sim::hash_text(hash.whole());
    j["simulation_hash"] = sim::hash_text(hash.simulation);
    j["watchpoints_hash"] = sim::hash_text(hash.watches);
    uint64_t total = 0;
    j["watches"] = nlohmann::json::array();
    for (uint32_t w = 0; w < model.watches.size(); ++w) {
      total += counts[w];
      auto entry = stats_json(model.watches[w].watchpoint, totals[w], counts[w]);
      const sim::HostedWatchpoint& h = model.watches[w];
      entry["algorithm"] = watch::algorithm_name(h.algorithm);
      entry["shape"] = watch::shape_name(watch::group_shape(h.algorithm, h.options));
      if (h.algorithm == watch::Algorithm::Distributed)
        entry["states"] = watch::states_name(h.options.states.value_or(watch::States::Consistent));
      entry["action"] = sim::action_name(model.watches[w].action);
      if (!h.watchpoint.program.actions.empty()) {  // docs/design.md §4b: what its matches' actions did
        entry["actions_done"] = run.head().watches[w].actions_done;
        entry["actions_skipped"] = run.head().watches[w].actions_skipped;
      }
      j["watches"].push_back(std::move(entry));
    }
    j["matches"] = total;
    if (pause)
      j["pause"] = {{"watch", model.watches[pause->watch].watchpoint.name},
                    {"t", pause->t},
                    {"detected", pause->detected},
                    {"group", pause->group},
                    {"rolled_back", rolled_back}};
    *stats << j.dump(1) << "\n";
  }
  if (const int code = interrupted("after " + std::to_string(ran) + " of " + std::to_string(steps) +
                                   " steps, while its outputs were made");
      code != 0)
    return code;
  if (!shell::commit_outputs({record_out.get(), matches_out.get(), stats_out.get(), render_out.get()})) return 1;
  return stopped ? 1 : 0;
}

}  // namespace

void add_run_command(CLI::App& app, std::function<int()>& run, sim::RankExchange* ranks,
                     shell::Interrupts* interrupts) {
  auto* cmd = app.add_subcommand("run", "Run a scenario headless, watchpoints live");
  auto args = std::make_shared<RunArgs>();
  cmd->add_option("scenario", args->scenario, "Scenario file (TOML)")->required();
  shell::add_integer_option(*cmd, "--steps", args->steps, scenarios::kStepsRange,
                            "Steps to run (default: the scenario's)");
  shell::add_integer_option(*cmd, "--seed", args->seed, scenarios::kSeedRange, "Random seed (default: the scenario's)");
  shell::add_integer_option(*cmd, "--threads,-j", args->threads, scenarios::kThreadsRange,
                            "Threads stepping modules (results never depend on it)");
  shell::add_integer_option(*cmd, "--history-mb", args->history_mb, scenarios::kHistoryRange,
                            "Memory for the history's keyframes, in MiB (default: the scenario's)");
  cmd->add_option("--algorithm", args->algorithm, "Run every watchpoint with this algorithm")
      ->check(CLI::IsMember({"centralized", "distributed"}));
  cmd->add_option("--shape", args->shape, "Run every watchpoint finding these groups: chain, ordered or any")
      ->check(CLI::IsMember({"chain", "ordered", "any"}));
  cmd->add_option("--states", args->states,
                  "Run every distributed watchpoint over consistent (the paper's) or simultaneous states")
      ->check(CLI::IsMember({"consistent", "simultaneous"}));
  shell::add_integer_option(*cmd, "--max-live", args->max_live, scenarios::kMaxLiveRange,
                            "Budget of every watchpoint: most PatternMatchers alive in one step; past it the run stops "
                            "(exit 1). 0: none (default: each watchpoint's max_live)");
  cmd->add_option("--partition", args->partition,
                  "Over several ranks (mpirun), share the modules in runs of blocks (slabs of a lattice), by a "
                  "METIS partition of their neighbour graph, or (auto) by blocks for a static lattice and by METIS "
                  "when bodies move")
      ->check(CLI::IsMember(std::vector<std::string>(sim::kPartitionNames.begin(), sim::kPartitionNames.end())));
  cmd->add_option("--record", args->record_path, "Write what the watchpoints saw as a wptrace v1 TRACE");
  cmd->add_option("--matches", args->matches_path,
                  "Write every match of log/pause watchpoints as JSON Lines (- for stdout)");
  cmd->add_option("--stats", args->stats_path, "Write run statistics as JSON");
  cmd->add_option("--render", args->render_path,
                  "Draw the 3D view to a PNG: at the first pause's step with its group, else at the last step");
  shell::add_integer_option(*cmd, "--print", args->print, {"print", 0, 1'000'000},
                            "Matches to print per watchpoint when --matches is not given")
      ->default_val(5);
  cmd->add_flag("--no-progress", args->no_progress, "No progress bar, even on a terminal");
  shell::add_memory_check_flag(*cmd, args->no_memory_check);
  cmd->callback([&run, args, ranks, interrupts] {
    run = [args, ranks, interrupts] { return run_scenario(*args, ranks, interrupts); };
  });
}

}  // namespace dw::app
