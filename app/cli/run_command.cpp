// `dwatch run SCENARIO`: run a scenario headless with its watchpoints live (docs/design.md §6).
#include <sys/resource.h>
#include <algorithm>
#include <array>
#include <chrono>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <variant>

#include "app/cli/commands.h"
#include "app/cli/progress.h"
#include "app/cli/run_summary.h"
#include "scenarios/scenario.h"
#include "shell/integer_option.h"
#include "shell/options.h"
#include "shell/output_files.h"
#include "shell/view_image.h"
#include "sim/run_outputs.h"
#include "sim/session.h"

namespace dw::app {
namespace {

struct RunArgs {
  std::string scenario;
  std::optional<int64_t> steps, seed, threads, history_mb, max_live, max_live_all, lua_seconds;
  std::string algorithm, shape, states, partition = "auto";
  std::string record_path, matches_path, stats_path, render_path;
  size_t print = 5;
  bool no_progress = false;
  bool no_memory_check = false;
  bool record_messages = false;  // each trace line says what its module read
};

// The scenario with the command line's overrides, or its diagnostics.
std::variant<scenarios::Scenario, std::string> load(const RunArgs& args) {
  scenarios::ScenarioOverrides overrides;
  if (args.seed) overrides.seed = static_cast<uint64_t>(*args.seed);
  if (!args.algorithm.empty()) overrides.algorithm = watch::parse_algorithm(args.algorithm);
  if (!args.shape.empty()) overrides.shape = watch::parse_shape(args.shape);
  if (!args.states.empty()) overrides.states = watch::parse_states(args.states);
  if (args.max_live) overrides.max_live = static_cast<uint64_t>(*args.max_live);
  overrides.memory_limit = shell::memory_limit_unless(args.no_memory_check);
  return scenarios::load_scenario(args.scenario, overrides);
}

// The files a run writes: only rank 0 opens them, and writes them whole or not at all.
struct RunFiles {
  explicit RunFiles(const RunArgs& args)
      : named{{{"--record", args.record_path},
               {"--matches", args.matches_path},
               {"--stats", args.stats_path},
               {"--render", args.render_path}}} {}
  // The summary goes to standard output unless an output does ("-"): redirected onto an output's
  // file (`--matches o.txt > o.txt`), it would be lost under the output committed over it.
  bool open(std::vector<std::string> inputs) {
    const bool summary_on_stdout =
        std::none_of(named.begin(), named.end(), [](const auto& f) { return f.path == "-"; });
    if (summary_on_stdout) inputs.emplace_back(shell::kStandardOutput);
    if (!shell::check_distinct_files(inputs, {named.begin(), named.end()}, "where the summary goes")) return false;
    for (size_t i = 0; i < named.size(); ++i)
      if (!shell::open_output(named[i], out[i])) return false;
    return true;
  }
  std::ostream* stream(size_t i) const { return shell::stream_of(out[i]); }
  bool commit() const { return shell::commit_outputs({out[0].get(), out[1].get(), out[2].get(), out[3].get()}); }
  static constexpr size_t kRecord = 0, kMatches = 1, kStats = 2, kRender = 3;
  std::array<shell::NamedFile, 4> named;
  std::array<std::unique_ptr<sim::OutputFile>, 4> out;
};

// A signal stops the run between steps, the outputs left uncommitted. Over ranks every rank would
// have to stop at the same step: a signal ends each at once instead. A signal that stopped the
// stepping, or came while the outputs were made, leaves nothing written; only the commits,
// together at the end, are not stoppable: a signal then ends the process at once, each output
// complete or as it was.
class RunStop {
 public:
  RunStop(shell::Interrupts* interrupts, bool over_ranks) : interrupts_(over_ranks ? nullptr : interrupts) { arm(); }
  sim::Control control() const { return {stoppable_ ? stoppable_->token() : std::stop_token{}, {}}; }
  // Stoppable again, while the outputs are made.
  void arm() {
    if (interrupts_) stoppable_.emplace(*interrupts_);
  }
  // The exit code of a signal that came (said on `errors`, `when` it came), or 0.
  int interrupted(std::ostream& errors, const RunArgs& args, const RunFiles& files, const std::string& when) {
    const std::optional<int> signal = stoppable_ ? stoppable_->signal() : std::nullopt;
    stoppable_.reset();
    if (!signal) return 0;
    errors << "dwatch: run " << args.scenario << " interrupted (" << shell::Interrupts::name(*signal) << ") " << when
           << ": nothing written";
    std::string kept;
    for (const shell::NamedFile& f : files.named)
      if (!f.path.empty() && f.path != "-") kept += (kept.empty() ? "" : ", ") + f.what + " " + f.path;
    if (!kept.empty()) errors << " (" << kept << ": as they were before the run)";
    errors << "\n";
    return shell::Interrupts::exit_code(*signal);
  }

 private:
  shell::Interrupts* interrupts_;
  std::optional<shell::Interrupts::Stoppable> stoppable_;
};

// The run's first lines: the ensemble, the steps, seed, threads and ranks, the programs.
void print_run_header(std::ostream& summary, const RunArgs& args, const scenarios::Scenario& scenario,
                      const sim::Session& run, int64_t steps, unsigned threads, const sim::RankExchange* ranks) {
  const sim::Model& model = *scenario.model;
  const auto& spec = model.lattice.spec;
  const auto& occupied = model.lattice.occupied;
  const size_t present = static_cast<size_t>(std::count(occupied.begin(), occupied.end(), 1));
  const int64_t ran = run.latest() + 1;
  summary << "run " << args.scenario << ": " << present << " modules (" << sim::lattice_name(spec.kind) << " "
          << spec.size[0];
  for (int d = 1; d < sim::lattice_dimensions(spec.kind); ++d) summary << "x" << spec.size[size_t(d)];
  if (present < occupied.size()) summary << ", " << occupied.size() - present << " cells left empty";
  summary << "), " << ran << (ran == 1 ? " step" : " steps") << " of " << steps << ", seed " << model.seed << ", "
          << threads << (threads == 1 ? " thread" : " threads");
  if (ranks)
    summary << " on each of " << ranks->ranks() << " ranks (partition: " << sim::partition_name(run.partition()) << ")";
  summary << "\n  programs:";
  for (const auto& p : model.programs) summary << " " << p->name();
  summary << "; " << run.head().program_messages << " program messages\n";
}

// Each watchpoint's line, its first matches (unless they went to --matches), its statistics and
// what its actions did; whether one's budget stopped it.
bool print_run_watches(std::ostream& summary, std::ostream& errors, const sim::Session& run,
                       const std::optional<sim::Pause>& pause, bool listed_elsewhere, size_t print) {
  bool stopped = false;
  for (uint32_t w = 0; w < run.watches().size(); ++w) {
    const sim::HostedWatchpoint& h = run.watches()[w].hosted;
    const std::vector<std::string>& slot_names = h.watchpoint.program.slot_names;
    const uint64_t count = run.match_count(w);
    summary << "  " << h.watchpoint.name << " ["
            << reading_text(h.algorithm, h.options, h.watchpoint.program.slot_count()) << ", "
            << sim::action_name(h.action) << "]: " << count << " match" << (count == 1 ? "" : "es");
    if (pause && pause->watch == w) {
      summary << "; PAUSED at step " << pause->t;
      if (pause->detected != pause->t) summary << " (detected at step " << pause->detected << ")";
      summary << ": " << group_text(slot_names, pause->group);
      if (pause->matches > 1) summary << " and " << pause->matches - 1 << " more at that step";
    }
    summary << "\n";
    const sim::MatchList& list = run.matches(w);
    const size_t k = slot_names.size();
    if (!listed_elsewhere)
      print_first_matches(summary, slot_names, list.size(), print, [&](size_t i) {
        return std::pair{list.t[i], std::span<const watch::ModuleId>(list.slots.data() + i * k, k)};
      });
    print_detector_stats(summary, run.stats(w));
    if (!h.watchpoint.program.actions.empty())
      summary << "    actions: " << run.head().watches[w].actions_done << " done, "
              << run.head().watches[w].actions_skipped << " skipped (value unknown, module gone or no such variable)\n";
    stopped = say_stopped(errors, h.watchpoint.name, run.stats(w), "max_live") || stopped;
  }
  return stopped;
}

// What a run measured besides its matches: its time, peak memory, the bytes between ranks (each
// over ranks, a collective call) and the state hash of the step it stands at.
struct RunMeasures {
  double seconds = 0, setup_seconds = 0, physics_seconds = 0;
  uint64_t between_ranks = 0, peak_kib = 0, peak_kib_all = 0;
  sim::StateHash hash;
};

RunMeasures measure(sim::Session& run, sim::RankExchange* ranks, std::chrono::steady_clock::time_point started,
                    std::chrono::steady_clock::time_point stepping) {
  RunMeasures m;
  const auto now = std::chrono::steady_clock::now();
  m.seconds = std::chrono::duration<double>(now - started).count();
  m.setup_seconds = std::chrono::duration<double>(stepping - started).count();
  m.hash = run.hash();
  m.between_ranks = run.bytes_to_ranks();
  if (ranks) ranks->sum({&m.between_ranks, 1});
  // Peak memory: this process's, and over ranks the largest rank's and all ranks' together.
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  m.peak_kib_all = static_cast<uint64_t>(usage.ru_maxrss);
  m.peak_kib = sim::max_over_ranks(ranks, m.peak_kib_all);
  if (ranks) ranks->sum({&m.peak_kib_all, 1});
  // The physics part of the steps: over ranks, the slowest rank's.
  m.physics_seconds = sim::max_over_ranks(ranks, run.world_seconds());
  return m;
}

void print_measures(std::ostream& summary, const RunMeasures& m, const sim::Session& run, bool moves,
                    const sim::RankExchange* ranks) {
  const int64_t ran = run.latest() + 1;
  const double step_seconds = m.seconds - m.setup_seconds;
  summary << std::fixed << std::setprecision(3) << "  time: " << m.seconds << " s (set-up " << m.setup_seconds
          << " s, steps " << step_seconds << " s";
  if (ran > 0 && run.model().module_count() > 0)
    summary << std::setprecision(2) << ", " << step_seconds * 1e9 / double(ran) / run.model().module_count()
            << " ns per module-step";
  summary << ")";
  if (moves && ran > 0)
    summary << std::setprecision(2) << "\n  physics: " << m.physics_seconds << " s of the steps, "
            << 1e3 * m.physics_seconds / double(ran) << " ms a step (bodies, contacts, the graph"
            << (ranks ? "; the slowest rank's)" : ")");
  summary << "\n  state hash: " << sim::hash_text(m.hash) << "\n";
  summary << "  run hash: " << sim::hash_text(m.hash.run) << " (every step's simulation hash, chained)\n";
  if (ranks && ran > 0)
    summary << "  between ranks: " << m.between_ranks << " bytes, " << m.between_ranks / uint64_t(ran)
            << " per step (program messages and PatternMatchers)\n";
}

// --stats: the run's facts and measures, each watchpoint's statistics, reading and actions, and
// the pause that stopped it.
nlohmann::ordered_json run_stats_json(const RunArgs& args, const scenarios::Scenario& scenario, const sim::Session& run,
                                      const RunMeasures& m, unsigned threads, const sim::RankExchange* ranks,
                                      const std::optional<sim::Pause>& pause) {
  const sim::Model& model = *scenario.model;
  nlohmann::ordered_json j;
  j["scenario"] = args.scenario;
  j["modules"] = static_cast<size_t>(std::count(model.lattice.occupied.begin(), model.lattice.occupied.end(), 1));
  j["steps"] = run.latest() + 1;
  j["seed"] = model.seed;
  j["threads"] = threads;
  j["ranks"] = ranks ? ranks->ranks() : 1;
  if (ranks) j["partition"] = std::string(sim::partition_name(run.partition()));
  j["bytes_between_ranks"] = m.between_ranks;
  j["peak_mib"] = double(m.peak_kib) / 1024;  // of the largest rank
  j["peak_mib_all_ranks"] = double(m.peak_kib_all) / 1024;
  j["seconds"] = m.seconds;
  j["setup_seconds"] = m.setup_seconds;
  if (scenario.world->moves()) j["physics_seconds"] = m.physics_seconds;
  j["program_messages"] = run.head().program_messages;
  j["state_hash"] = sim::hash_text(m.hash.whole());
  j["simulation_hash"] = sim::hash_text(m.hash.simulation);
  j["watchpoints_hash"] = sim::hash_text(m.hash.watches);
  j["run_hash"] = sim::hash_text(m.hash.run);
  uint64_t total = 0;
  j["watches"] = nlohmann::json::array();
  for (uint32_t w = 0; w < run.watches().size(); ++w) {
    const sim::HostedWatchpoint& h = run.watches()[w].hosted;
    const sim::WatchSpec spec = sim::spec_of(h);
    total += run.match_count(w);
    nlohmann::ordered_json entry = stats_json(spec, run.stats(w), run.match_count(w));
    add_reading_json(entry, spec);
    if (!h.watchpoint.program.actions.empty()) {  // docs/design.md §4b: what its matches' actions did
      entry["actions_done"] = run.head().watches[w].actions_done;
      entry["actions_skipped"] = run.head().watches[w].actions_skipped;
    }
    j["watches"].push_back(std::move(entry));
  }
  j["matches"] = total;
  if (pause)
    j["pause"] = {{"watch", run.watches()[pause->watch].hosted.watchpoint.name},
                  {"t", pause->t},
                  {"detected", pause->detected},
                  {"group", pause->group},
                  {"rolled_back", run.current() < run.latest()}};
  return j;
}

// --render: the view at the paused match's step with its group, or at the last step run (over
// ranks, a collective call; only rank 0 draws). An exit code when it failed.
std::optional<int> render_run(std::ostream& summary, const RunArgs& args, const scenarios::Scenario& scenario,
                              sim::Session& run, const std::optional<sim::Pause>& pause, sim::OutputFile& out,
                              bool lead) {
  const int64_t shown = std::max<int64_t>(0, run.current());
  std::vector<render::SceneGroup> groups;
  if (pause && shown == pause->t) {
    const watch::Watchpoint& w = run.watches()[pause->watch].hosted.watchpoint;
    groups.push_back({w.name, pause->t, w.program.slot_names, pause->group});
  }
  render::SceneSettings settings = shell::scene_settings(scenario, "");
  settings.title = scenario.name + "  \xC2\xB7  step " + std::to_string(shown);
  sim::State whole = run.state();  // over ranks, the variables of every rank's modules
  whole.values = run.whole_values(whole);
  if (!lead) return std::nullopt;
  const render::Scene scene = render::build_scene(*scenario.model, whole, groups, settings);
  if (shell::camera_refused(scene, 1280, 720)) return 2;
  if (std::string error = shell::write_view(scene, out, 1280, 720); !error.empty()) {
    std::cerr << "dwatch: error: " << error << "\n";
    return 1;
  }
  summary << "  view of step " << shown << " written to " << args.render_path << "\n";
  return std::nullopt;
}

// Runs the steps with the outputs written as they come (sim/run_outputs.h), then the run's end (a
// drain or the pause line): the pause that stopped it, or the exit code of what stopped the run.
// `with_messages`: the trace, written here rather than by `outputs`, each line with what its module
// read at its step (the inbox the step before left).
std::variant<std::optional<sim::Pause>, int> step_run(sim::Session& run, sim::RunOutputs& outputs, RunStop& stop,
                                                      const RunArgs& args, const RunFiles& files, int64_t steps,
                                                      ProgressBar& progress, std::ostream& errors,
                                                      sim::TraceWriter* with_messages) {
  const sim::Model& model = run.model();
  const bool recording = !args.record_path.empty();  // on every rank: each gives its part of each frame
  sim::Mailbox read = run.head().inbox;              // what step 0 reads
  std::optional<sim::Pause> pause;
  try {
    pause = run.run_until(
        steps,
        [&](const sim::State& state, const sim::StepOutput& out) {
          std::vector<int64_t> values;
          std::shared_ptr<const sim::NeighborGraph> graph;
          std::optional<watch::Frame> frame;
          if (recording) {
            values = run.whole_values(state);
            graph = run.whole_graph(out.graph);
            if (outputs.recording() || with_messages)
              frame = sim::make_frame(model, out.step, values, out.present, graph);
          }
          if (with_messages && frame) {
            with_messages->write(*frame, &read);
            read = state.inbox;
          }
          outputs.step(out, frame && !with_messages ? &*frame : nullptr);
          progress.update(out.step + 1);
        },
        stop.control());
    if (const int code =
            stop.interrupted(errors, args, files,
                             "after " + std::to_string(run.latest() + 1) + " of " + std::to_string(steps) + " steps");
        code != 0) {
      progress.finish();
      return code;
    }
    stop.arm();
    outputs.end_run(run, pause, steps);
    if (with_messages && pause)
      with_messages->write_paused({run.watches()[pause->watch].hosted.watchpoint.name, pause->t});
  } catch (const sim::ProgramError& e) {
    progress.finish();
    errors << "dwatch: " << args.scenario << ": error: " << e.what() << "\n";
    return 1;
  }
  return pause;
}

int run_scenario(const RunArgs& args, sim::RankExchange* ranks, shell::Interrupts* interrupts) {
  // The time reported covers the set-up too: loading, the world, the first state.
  const auto started = std::chrono::steady_clock::now();
  // Over several ranks, rank 0 speaks and writes the outputs; every rank runs its part.
  const bool lead = ranks == nullptr || ranks->rank() == 0;
  std::ostream quiet(nullptr);
  std::ostream& errors = lead ? std::cerr : quiet;
  auto loaded = load(args);
  if (auto* message = std::get_if<std::string>(&loaded)) {
    errors << *message;
    return 2;
  }
  scenarios::Scenario& scenario = std::get<scenarios::Scenario>(loaded);
  if (args.lua_seconds) scenario.lua_memory->set_seconds(*args.lua_seconds);
  const sim::Model& model = *scenario.model;
  const int64_t steps = args.steps.value_or(scenario.steps);
  const unsigned threads = args.threads ? static_cast<unsigned>(*args.threads) : scenario.threads;
  const size_t history_mb = args.history_mb ? static_cast<size_t>(*args.history_mb) : scenario.history_mb;

  if (args.render_path == "-") {
    errors << "dwatch: error: --render needs a file name\n";
    return 2;
  }
  if (ranks && args.record_messages) {
    errors << "dwatch: error: --record-messages records one process's run: run it without mpirun\n";
    return 2;
  }
  if (ranks) {
    if (const std::string why = sim::why_not_over_ranks(model); !why.empty()) {
      errors << "dwatch: error: " << args.scenario << " cannot run over " << ranks->ranks() << " ranks: " << why
             << "\n";
      return 2;
    }
  }
  RunFiles files(args);
  // Only rank 0 opens the outputs; if it cannot, every rank stops.
  if (sim::any_rank(ranks, lead && !files.open(scenario.inputs))) return 2;
  const bool to_stdout = args.record_path == "-" || args.matches_path == "-" || args.stats_path == "-";

  sim::SessionOptions options{threads,         steps, history_mb << 20,
                              scenario.events, ranks, sim::partition_named(args.partition)};
  if (args.max_live_all) options.run_live_budget = static_cast<uint64_t>(*args.max_live_all);
  sim::Session run(*scenario.model, *scenario.world, options);
  sim::RunOutputs outputs(run.watches().hosted(), files.stream(RunFiles::kMatches), 1);
  std::optional<sim::TraceWriter> with_messages;
  if (std::ostream* record = files.stream(RunFiles::kRecord)) {
    if (args.record_messages)
      with_messages.emplace(*record, model.universe, scenario.events, sim::specs_of(run.watches().hosted()));
    else outputs.record(*record, model.universe, scenario.events);
  }
  ProgressBar progress("run " + scenario.name, steps, lead && !args.no_progress);
  const auto stepping = std::chrono::steady_clock::now();
  RunStop stop(interrupts, ranks != nullptr);
  auto stepped =
      step_run(run, outputs, stop, args, files, steps, progress, errors, with_messages ? &*with_messages : nullptr);
  if (const int* code = std::get_if<int>(&stepped)) return *code;
  const std::optional<sim::Pause>& pause = std::get<std::optional<sim::Pause>>(stepped);
  std::vector<uint64_t> counts;
  for (uint32_t w = 0; w < run.watches().size(); ++w) counts.push_back(run.match_count(w));
  outputs.finish(counts);
  progress.finish();
  const RunMeasures measures = measure(run, ranks, started, stepping);

  std::ostream& summary = !lead ? quiet : to_stdout ? std::cerr : std::cout;
  print_run_header(summary, args, scenario, run, steps, threads, ranks);
  const bool stopped =
      print_run_watches(summary, errors, run, pause, files.stream(RunFiles::kMatches) != nullptr, args.print);
  // The session stands at the paused match's step (or the last one run): the state shown and
  // hashed is that step's. Counts and statistics are of everything run.
  if (pause && run.current() < run.latest())
    summary << "  rolled back to step " << pause->t << ", the paused match's step\n";
  print_measures(summary, measures, run, scenario.world->moves(), ranks);
  if (!args.render_path.empty()) {
    if (const auto code = render_run(summary, args, scenario, run, pause, *files.out[RunFiles::kRender], lead))
      return *code;
    if (!lead) return stopped ? 1 : 0;
  }
  if (std::ostream* stats = files.stream(RunFiles::kStats))
    *stats << run_stats_json(args, scenario, run, measures, threads, ranks, pause).dump(1) << "\n";
  const int64_t ran = run.latest() + 1;
  if (const int code = stop.interrupted(
          errors, args, files,
          "after " + std::to_string(ran) + " of " + std::to_string(steps) + " steps, while its outputs were made");
      code != 0)
    return code;
  if (!files.commit()) return 1;
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
  shell::add_integer_option(*cmd, "--max-live-all", args->max_live_all, scenarios::kMaxLiveRange,
                            "Budget of all watchpoints together: most PatternMatchers alive in one step, charged in "
                            "watchpoint order (those with actions first); the watchpoint that passes it and those "
                            "after it stop (exit 1). 0: none")
      ->default_val(sim::kDefaultRunBudget);
  shell::add_integer_option(*cmd, "--lua-seconds", args->lua_seconds, scenarios::kLuaSecondsRange,
                            "Wall-clock seconds all the run's Lua calls may take together, besides 10 s a call "
                            "(exit 1 past it). 0: none")
      ->default_val(scenarios::LuaMemoryPool::kDefaultSeconds);
  cmd->add_option("--partition", args->partition,
                  "Over several ranks (mpirun), share the modules in runs of blocks (slabs of a lattice), by a "
                  "METIS partition of their neighbour graph, or (auto) by blocks for a static lattice and by METIS "
                  "when bodies move")
      ->check(CLI::IsMember(std::vector<std::string>(sim::kPartitionNames.begin(), sim::kPartitionNames.end())));
  cmd->add_option("--record", args->record_path, "Write what the watchpoints saw as a wptrace v1 TRACE");
  cmd->add_flag("--record-messages", args->record_messages,
                "With --record, each line also says what its module read (\"recv\": sender, step sent, words), "
                "for `dwatch why TRACE` (one process only)")
      ->needs("--record");
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
