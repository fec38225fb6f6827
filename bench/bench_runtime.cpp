// The runtime benchmarks: Table I, the watchpoint overhead and the million-module run, each with
// the host programs running and the watchpoints live, as `dwatch run` would run them. Scenarios
// are written as TOML and go through the scenario loader like any file.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include "bench/bench.h"
#include "bench/bench_child.h"
#include "bench/shipped_files.h"
#include "scenarios/scenario.h"
#include "shell/output_files.h"
#include "sim/session.h"

namespace dw::bench {

std::string cubic_toml(uint32_t nx, uint32_t ny, uint32_t nz) {
  return "[lattice]\nkind = \"cubic\"\nsize = [" + std::to_string(nx) + ", " + std::to_string(ny) + ", " +
         std::to_string(nz) + "]\n";
}

std::string random_vars_toml(std::span<const int64_t> maxima) {
  std::string list;
  for (int64_t m : maxima) list += (list.empty() ? "" : ", ") + std::to_string(m);
  return "[[program]]\nname = \"random_vars\"\ntuple = [" + list + "]\n";
}

std::string watch_toml(const std::string& name, const std::string& text, watch::Algorithm a,
                       const shell::DetectorFlags& flags) {
  std::string t = "[[watch]]\nname = \"" + name + "\"\naction = \"count\"\nalgorithm = \"" + watch::algorithm_name(a) +
                  "\"\ntext = \"" + text + "\"\nmax_live = " + std::to_string(flags.max_live) + "\n";
  if (flags.no_early_termination) t += "early_termination = false\n";
  if (flags.no_neighbor_culling) t += "neighbor_culling = false\n";
  if (flags.no_temporal_spans) t += "temporal_spans = false\n";
  if (!flags.shape_name.empty()) t += "shape = \"" + flags.shape_name + "\"\n";
  if (!flags.states_name.empty()) t += "states = \"" + flags.states_name + "\"\n";
  return t;
}

std::string million_toml(uint32_t size, shell::DetectorFlags flags) {
  // The default budget is sized for a million modules; a larger ensemble gets as much per module.
  const uint64_t modules = uint64_t{size} * size * size;
  if (flags.max_live == shell::DetectorFlags{}.max_live && modules > 1'000'000)
    flags.max_live = modules / 1'000'000 * flags.max_live;
  return cubic_toml(size, size, size) + random_vars_toml(parse_tuple("8:4:2:1")) +
         watch_toml("fig6", kFig6, watch::Algorithm::Distributed, flags);
}

namespace {

// One run of the scenario from scratch: the seconds its timed part took, or a negative number,
// with the error on stderr, when the scenario does not load. Fills in the first watch's counts.
double run_scenario_once(const std::string& text, const BenchArgs& args, Timed timed, RuntimeRow& row) {
  auto load = [&]() -> std::optional<scenarios::Scenario> {
    auto loaded = scenarios::load_scenario_text("bench.toml", text);
    if (auto* e = std::get_if<std::string>(&loaded)) {
      std::cerr << *e;
      return std::nullopt;
    }
    return std::move(std::get<scenarios::Scenario>(loaded));
  };
  const sim::SessionOptions options{.threads = args.threads, .history_bytes = 0};  // no history: the runtime alone
  if (timed == Timed::SetUp) {
    const auto start = std::chrono::steady_clock::now();
    {
      const std::optional<scenarios::Scenario> s = load();
      if (!s) return -1;
      sim::Session run(*s->model, *s->world, options);
    }
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  const std::optional<scenarios::Scenario> s = load();
  if (!s) return -1;
  sim::Session run(*s->model, *s->world, options);
  const auto start = std::chrono::steady_clock::now();
  run.run_until(args.steps);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  row.world_seconds = run.world_seconds();
  if (!s->model->watches.empty()) {
    row.matches = run.match_count(0);
    row.created = run.stats(0).created;
    row.messages = run.stats(0).messages;
    row.stopped = run.stats(0).stopped;
  }
  return seconds;
}

// Runs the scenario `repeat` times, or more until the runs add up to `min_seconds`; the fastest
// run is the figure.
RuntimeRow run_scenario_text(const std::string& toml, const BenchArgs& args, int repeat, Timed timed,
                             double min_seconds) {
  constexpr size_t kMostRuns = 100;
  const std::string text = "seed = " + std::to_string(args.seed) + "\n" + toml;
  RuntimeRow row;
  std::vector<double> times;
  double total = 0, best_world = 0;
  while (times.size() < size_t(repeat) || (total < min_seconds && times.size() < kMostRuns)) {
    const double seconds = run_scenario_once(text, args, timed, row);
    if (seconds < 0) {
      row.failed = true;
      return row;
    }
    if (times.empty() || seconds < *std::min_element(times.begin(), times.end())) best_world = row.world_seconds;
    times.push_back(seconds);
    total += seconds;
  }
  std::sort(times.begin(), times.end());
  row.seconds = times.front();
  row.median_seconds = times[times.size() / 2];
  row.world_seconds = best_world;
  return row;
}

}  // namespace

bool run_runtime_row(const std::string& toml, const BenchArgs& args, int repeat, RuntimeRow& row, Timed timed,
                     double min_seconds) {
  long peak_kib = 0;
  if (!in_child([&] { return run_scenario_text(toml, args, repeat, timed, min_seconds); }, row, peak_kib) ||
      row.failed) {
    std::cerr << "dwatch bench: error: the benchmark run failed\n";
    return false;
  }
  row.peak_kib = peak_kib;
  return true;
}

namespace {

struct Table {
  std::unique_ptr<sim::OutputFile> csv;  // --out DIR: DIR/NAME.csv
  bool stopped = false;                  // some row's watch reached its budget
};

// Runs one row in a child process and prints it; false when it failed.
bool row(const std::string& label, const std::string& toml, const BenchArgs& args, int repeat, Table& table,
         RuntimeRow& out, Timed timed = Timed::Steps) {
  if (!run_runtime_row(toml, args, repeat, out, timed)) return false;
  const double mib = static_cast<double>(out.peak_kib) / 1024.0;
  std::cout << std::left << std::setw(40) << label << std::right << std::setw(12) << out.matches << std::setw(14)
            << out.created << std::setw(10) << std::fixed << std::setprecision(3) << out.seconds << std::setw(10)
            << out.median_seconds << std::setw(11) << std::setprecision(1) << mib
            << (out.stopped ? "  stopped at the --max-live budget" : "") << "\n";
  if (table.csv)
    table.csv->stream() << '"' << label << "\"," << out.matches << "," << out.created << "," << out.messages << ","
                        << out.seconds << "," << out.median_seconds << "," << mib << "," << out.stopped << "\n";
  if (out.stopped) table.stopped = true;
  return true;
}

void header(const std::string& title) {
  std::cout << title << "\n"
            << std::left << std::setw(40) << "row" << std::right << std::setw(12) << "matches" << std::setw(14)
            << "created" << std::setw(10) << "best s" << std::setw(10) << "median s" << std::setw(11) << "peak MiB\n";
}

int run_rows(const BenchArgs& args, Table& table);

}  // namespace

int bench_runtime(const BenchArgs& args) {
  Table table;
  if (!open_csv(args, args.name, "row,matches,created,messages,best_seconds,median_seconds,peak_mib,stopped",
                table.csv))
    return 2;
  const int status = run_rows(args, table);
  if (!shell::commit_outputs({table.csv.get()})) return 1;
  return status != 0 ? status : table.stopped ? 1 : 0;
}

namespace {

// The Fig. 6 watch as the command's flags read it (bench.h: watch_toml).
std::string fig6_toml(const BenchArgs& args, watch::Algorithm a) { return watch_toml("fig6", kFig6, a, args.detector); }

// "1 thread", "4 threads": how many step the modules.
std::string threads_text(const BenchArgs& args) {
  return std::to_string(args.threads) + (args.threads == 1 ? " thread" : " threads");
}

// bench table1: Table I live, one row per tuple.
int table1_rows(const BenchArgs& args, Table& table) {
  auto fig6 = [&](watch::Algorithm a) { return fig6_toml(args, a); };
  const std::string threads = threads_text(args);
  RuntimeRow r;
  header("bench table1: " + std::to_string(args.size) + "^3 cube, " + std::to_string(args.steps) +
         " steps, random_vars + Fig. 6 live, distributed, " + threads);
  double total = 0;
  for (const std::string& tuple : args.tuples) {
    if (parse_tuple(tuple).empty()) {
      std::cerr << "dwatch bench: error: tuple '" << tuple << "' is not four positive integers like 2:2:2:2\n";
      return 2;
    }
    if (!row(tuple,
             cubic_toml(args.size, args.size, args.size) + random_vars_toml(parse_tuple(tuple)) +
                 fig6(watch::Algorithm::Distributed),
             args, args.repeat, table, r))
      return 1;
    total += r.seconds;
  }
  std::cout << std::fixed << std::setprecision(3) << "all rows: " << total << " s (best runs summed)\n";
  return 0;
}

// bench overhead: the watchpoint over the paper's medium-intensity workload (§V-B).
int overhead_rows(const BenchArgs& args, Table& table) {
  auto fig6 = [&](watch::Algorithm a) { return fig6_toml(args, a); };
  const std::string threads = threads_text(args);
  header("bench overhead: " + std::to_string(args.size) + "^3 cube, " + std::to_string(args.steps) +
         " steps, aggregation_routing (paper §V-B), " + threads);
  const std::string base = cubic_toml(args.size, args.size, args.size) + kAggregationToml;
  RuntimeRow alone, with_vars, central, distributed;
  if (!row("aggregation_routing", base, args, args.repeat, table, alone)) return 1;
  const std::string vars = base + random_vars_toml(parse_tuple("2:2:2:2"));
  if (!row("  + random_vars [2:2:2:2]", vars, args, args.repeat, table, with_vars)) return 1;
  if (!row("  + Fig. 6 centralized", vars + fig6(watch::Algorithm::Centralized), args, args.repeat, table, central))
    return 1;
  if (!row("  + Fig. 6 distributed", vars + fig6(watch::Algorithm::Distributed), args, args.repeat, table, distributed))
    return 1;
  std::cout << std::fixed << std::setprecision(1)
            << "watchpoint overhead over the workload with its variables: centralized "
            << 100 * (central.seconds / with_vars.seconds - 1) << "%, distributed "
            << 100 * (distributed.seconds / with_vars.seconds - 1) << "% (the paper: 118%, 105%)\n";
  return 0;
}

// bench physics: set-up and memory, resting lattices, islands in parallel, fcc beside cubic.
int physics_rows(const BenchArgs& args, Table& table) {
  const std::string threads = threads_text(args);
  RuntimeRow r;
  header("bench physics: resting lattices in the Bullet world, " + std::to_string(args.steps) +
         " steps, body_sense (neighbour count, speed) on every module, " + threads);
  const std::string sense = "[[program]]\nname = \"body_sense\"\n";
  const std::string latched = "[physics]\nenabled = true\n", free = latched + "anchor = false\n";
  auto per_step = [&](const RuntimeRow& x) {
    std::cout << "    " << std::fixed << std::setprecision(3) << 1000 * x.seconds / double(args.steps)
              << " ms per step (physics step, graph rebuild and programs)\n";
  };
  // Setting up a physics world is linear in the modules (physics/pair_cache.h says why it was not).
  // What a module costs: the peaks of 40^3 and 10^3 apart, over the 63,000 modules between.
  std::map<std::pair<uint32_t, bool>, long> peak_kib;
  for (const auto& [n, anchored] :
       {std::pair{10u, true}, {20u, true}, {30u, true}, {40u, true}, {10u, false}, {40u, false}}) {
    const std::string label = "set up and torn down, " + std::to_string(n) + "^3" + (anchored ? "" : " free");
    if (!row(label, cubic_toml(n, n, n) + sense + (anchored ? latched : free), args, args.repeat, table, r,
             Timed::SetUp))
      return 1;
    peak_kib[{n, anchored}] = r.peak_kib;
  }
  const auto per_module = [&](bool anchored) {
    return double(peak_kib[{40u, anchored}] - peak_kib[{10u, anchored}]) / (64'000 - 1'000);
  };
  std::cout << std::fixed << std::setprecision(2) << "    memory per module (40^3 peak - 10^3 peak, / 63,000): latched "
            << per_module(true) << " KiB (target 2), free " << per_module(false) << " KiB (target 4)\n";
  for (uint32_t n : {10u, 20u}) {
    const std::string side = std::to_string(n) + "^3";
    if (!row("resting " + side + ", latched to the ground", cubic_toml(n, n, n) + sense + latched, args, args.repeat,
             table, r))
      return 1;
    per_step(r);
    if (!row("resting " + side + ", free on the ground", cubic_toml(n, n, n) + sense + free, args, args.repeat, table,
             r))
      return 1;
    per_step(r);
  }
  // Islands in parallel: 64 free blocks of 4x4x3 resting on the ground a cell apart, each its
  // own island, stepped on one thread and on two.
  std::string blocks = cubic_toml(39, 39, 3);
  for (int i = 4; i < 39; i += 5)
    blocks += "[[lattice.empty]]\nfrom = [" + std::to_string(i) + ", 0, 0]\nto = [" + std::to_string(i) +
              ", 38, 2]\n[[lattice.empty]]\nfrom = [0, " + std::to_string(i) + ", 0]\nto = [38, " + std::to_string(i) +
              ", 2]\n";
  RuntimeRow on_one, on_two;
  BenchArgs two_threads = args;
  two_threads.threads = 2;
  BenchArgs one_thread = args;
  one_thread.threads = 1;
  if (!row("64 free blocks apart, 1 thread", blocks + sense + free, one_thread, args.repeat, table, on_one) ||
      !row("64 free blocks apart, 2 threads", blocks + sense + free, two_threads, args.repeat, table, on_two))
    return 1;
  std::cout << std::fixed << std::setprecision(2) << "    physics part: " << 1000 * on_one.world_seconds / args.steps
            << " ms a step on 1 thread, " << 1000 * on_two.world_seconds / args.steps << " ms on 2 ("
            << on_one.world_seconds / on_two.world_seconds << "x)\n";
  // Catoms 3D: an fcc block of 20x20x20 sites (8,000 spheres, 12 neighbours inside) beside the
  // 20^3 cubic one (6 neighbours), latched and resting.
  const std::string fcc = "[lattice]\nkind = \"fcc\"\nsize = [20, 20, 20]\n";
  RuntimeRow cubic_setup, cubic_step, fcc_setup, fcc_step;
  if (!row("set up and torn down, 20^3", cubic_toml(20, 20, 20) + sense + latched, args, args.repeat, table,
           cubic_setup, Timed::SetUp) ||
      !row("set up and torn down, fcc 20^3", fcc + sense + latched, args, args.repeat, table, fcc_setup,
           Timed::SetUp) ||
      !row("resting 20^3, latched", cubic_toml(20, 20, 20) + sense + latched, args, args.repeat, table, cubic_step) ||
      !row("resting fcc 20^3, latched", fcc + sense + latched, args, args.repeat, table, fcc_step))
    return 1;
  std::cout << std::fixed << std::setprecision(2) << "    fcc against cubic: set-up "
            << fcc_setup.seconds / cubic_setup.seconds << "x, steps " << fcc_step.seconds / cubic_step.seconds
            << "x (target 1.5)\n";
  return 0;
}

// bench physics at scale: a million modules set up, resting and flowing; the watchpoint over
// a physics run of leader election.
int physics_at_scale_rows(const BenchArgs& args, Table& table) {
  const std::string sense = "[[program]]\nname = \"body_sense\"\n";
  const std::string latched = "[physics]\nenabled = true\n", free = latched + "anchor = false\n";
  RuntimeRow r;
  // A million modules: a 100^3 block latched to the ground, set up; resting; and with the holes
  // of reconfigure_large.toml flowing through its top layer (1,000 modules set off at step 1,
  // hundreds glide at once after), the physics part of a step apart.
  const auto physics_part = [&](const RuntimeRow& x) {
    std::cout << "    physics part: " << std::fixed << std::setprecision(1)
              << 1000 * x.world_seconds / double(args.steps) << " ms a step (bodies, contacts, the graph)\n";
  };
  if (!row("set up and torn down, 100^3", cubic_toml(100, 100, 100) + sense + latched, args, 1, table, r, Timed::SetUp))
    return 1;
  if (!row("resting 100^3, latched to the ground", cubic_toml(100, 100, 100) + sense + latched, args, 1, table, r))
    return 1;
  physics_part(r);
  std::ifstream flow_file(shipped_files().scenarios + "/reconfigure_large.toml");
  std::stringstream flow;
  flow << flow_file.rdbuf();
  std::string flow_toml = flow.str();
  const size_t seed = flow_toml.find("\nseed = ");  // the bench gives the seed
  flow_toml.erase(seed, flow_toml.find('\n', seed + 1) - seed);
  if (!row("reconfigure_large 100^3 (surface flow)", flow_toml, args, 1, table, r)) return 1;
  physics_part(r);
  // The watchpoint's overhead over a 1,000-module physics run of leader election (hex 40x25).
  const std::string election =
      "[lattice]\nkind = \"hex2d\"\nsize = [40, 25]\n[[program]]\nname = \"leader_election\"\n";
  const std::string two_leaders = watch_toml("two_leaders", "modules(a b c); (a.isLeader = 1) and (c.isLeader = 1)",
                                             watch::Algorithm::Distributed, args.detector);
  for (const auto& [label, physics] : {std::pair{"latched", latched}, std::pair{"free", free}}) {
    RuntimeRow without, with;
    if (!row(std::string("leader_election 1000, ") + label, election + physics, args, args.repeat, table, without))
      return 1;
    if (!row("  + two_leaders, distributed", election + physics + two_leaders, args, args.repeat, table, with))
      return 1;
    std::cout << std::fixed << std::setprecision(1)
              << "    watchpoint overhead: " << 100 * (with.seconds / without.seconds - 1) << "%\n";
  }
  return 0;
}

// bench million: a 100^3 cube (or --size) of random_vars [8:4:2:1] with Fig. 6 live.
int million_rows(const BenchArgs& args, Table& table) {
  const std::string threads = threads_text(args);
  RuntimeRow r;
  const uint32_t size = args.size == 10 ? 100 : args.size;
  header("bench million: " + std::to_string(size) + "^3 cube, " + std::to_string(args.steps) +
         " steps, random_vars [8:4:2:1] + Fig. 6 live, distributed, " + threads);
  const uint64_t modules = uint64_t{size} * size * size;
  auto ensemble = [&](uint32_t n) { return million_toml(n, args.detector); };
  // The same run on 10^3 modules first: what a PatternMatcher costs when everything is in cache.
  RuntimeRow small;
  if (!row("8:4:2:1, 10^3 modules", ensemble(10), args, std::max(args.repeat, 5), table, small)) return 1;
  if (!row("8:4:2:1", ensemble(size), args, args.repeat, table, r)) return 1;
  // Thread-seconds of the whole step (programs and agents) per PatternMatcher created.
  auto ns_per_pm = [&](const RuntimeRow& x) {
    return 1e9 * x.seconds * args.threads / double(std::max<uint64_t>(1, x.created));
  };
  std::cout << std::fixed << std::setprecision(1) << "per PatternMatcher created: " << ns_per_pm(r) << " ns at " << size
            << "^3 against " << ns_per_pm(small) << " ns at 10^3 (" << std::setprecision(2)
            << ns_per_pm(r) / ns_per_pm(small) << "x; thread-seconds of the whole step)\n"
            << std::setprecision(0) << "memory: " << double(r.peak_kib) * 1024 / double(modules)
            << " bytes per module (peak resident set over the modules)\n";
  return 0;
}

// The rows of table1, overhead, million or physics.
int run_rows(const BenchArgs& args, Table& table) {
  if (args.name == "table1") return table1_rows(args, table);
  if (args.name == "overhead") return overhead_rows(args, table);
  if (args.name == "physics") {
    const int status = physics_rows(args, table);
    return status != 0 ? status : physics_at_scale_rows(args, table);
  }
  return million_rows(args, table);
}

}  // namespace

}  // namespace dw::bench
