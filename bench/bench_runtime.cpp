// The runtime benchmarks: Table I, the watchpoint overhead and the million-module run, each with
// the host programs running and the watchpoints live, as `dwatch run` would run them. Scenarios
// are written as TOML and go through the scenario loader like any file.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <optional>

#include "bench/bench.h"
#include "bench/bench_child.h"
#include "bench/runtime_rows.h"
#include "scenarios/scenario.h"
#include "shell/output_files.h"
#include "sim/session.h"

namespace dw::bench {

std::optional<scenarios::Scenario> load_bench_scenario(const std::string& text) {
  auto loaded = scenarios::load_scenario_text("bench.toml", text);
  if (auto* e = std::get_if<std::string>(&loaded)) {
    std::cerr << *e;
    return std::nullopt;
  }
  return std::move(std::get<scenarios::Scenario>(loaded));
}

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
  const auto load = [&] { return load_bench_scenario(text); };
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

// Runs one row in a child process and prints it; false when it failed.
bool print_runtime_row(const std::string& label, const std::string& toml, const BenchArgs& args, int repeat,
                       RuntimeTable& table, RuntimeRow& out, Timed timed) {
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

void print_runtime_header(const std::string& title) {
  std::cout << title << "\n"
            << std::left << std::setw(40) << "row" << std::right << std::setw(12) << "matches" << std::setw(14)
            << "created" << std::setw(10) << "best s" << std::setw(10) << "median s" << std::setw(11) << "peak MiB\n";
}

std::string threads_text(const BenchArgs& args) {
  return std::to_string(args.threads) + (args.threads == 1 ? " thread" : " threads");
}

namespace {

int run_rows(const BenchArgs& args, RuntimeTable& table);

}  // namespace

int bench_runtime(const BenchArgs& args) {
  if (args.name == "physics") return bench_physics(args);  // bench_physics.cpp
  RuntimeTable table;
  if (!open_csv(args, args.name, kRuntimeCsvHeader, table.csv)) return 2;
  const int status = run_rows(args, table);
  if (!shell::commit_outputs({table.csv.get()})) return 1;
  return status != 0 ? status : table.stopped ? 1 : 0;
}

namespace {

// The Fig. 6 watch as the command's flags read it (bench.h: watch_toml).
std::string fig6_toml(const BenchArgs& args, watch::Algorithm a) { return watch_toml("fig6", kFig6, a, args.detector); }

// bench table1: Table I live, one row per tuple.
int table1_rows(const BenchArgs& args, RuntimeTable& table) {
  auto fig6 = [&](watch::Algorithm a) { return fig6_toml(args, a); };
  const std::string threads = threads_text(args);
  RuntimeRow r;
  print_runtime_header("bench table1: " + std::to_string(args.size) + "^3 cube, " + std::to_string(args.steps) +
                       " steps, random_vars + Fig. 6 live, distributed, " + threads);
  double total = 0;
  for (const std::string& tuple : args.tuples) {
    if (parse_tuple(tuple).empty()) {
      std::cerr << "dwatch bench: error: tuple '" << tuple << "' is not four positive integers like 2:2:2:2\n";
      return 2;
    }
    if (!print_runtime_row(tuple,
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
int overhead_rows(const BenchArgs& args, RuntimeTable& table) {
  auto fig6 = [&](watch::Algorithm a) { return fig6_toml(args, a); };
  const std::string threads = threads_text(args);
  print_runtime_header("bench overhead: " + std::to_string(args.size) + "^3 cube, " + std::to_string(args.steps) +
                       " steps, aggregation_routing (paper §V-B), " + threads);
  const std::string base = cubic_toml(args.size, args.size, args.size) + kAggregationToml;
  RuntimeRow alone, with_vars, central, distributed;
  if (!print_runtime_row("aggregation_routing", base, args, args.repeat, table, alone)) return 1;
  const std::string vars = base + random_vars_toml(parse_tuple("2:2:2:2"));
  if (!print_runtime_row("  + random_vars [2:2:2:2]", vars, args, args.repeat, table, with_vars)) return 1;
  if (!print_runtime_row("  + Fig. 6 centralized", vars + fig6(watch::Algorithm::Centralized), args, args.repeat, table,
                         central))
    return 1;
  if (!print_runtime_row("  + Fig. 6 distributed", vars + fig6(watch::Algorithm::Distributed), args, args.repeat, table,
                         distributed))
    return 1;
  std::cout << std::fixed << std::setprecision(1)
            << "watchpoint overhead over the workload with its variables: centralized "
            << 100 * (central.seconds / with_vars.seconds - 1) << "%, distributed "
            << 100 * (distributed.seconds / with_vars.seconds - 1) << "% (the paper: 118%, 105%)\n";
  return 0;
}

// bench million: a 100^3 cube (or --size) of random_vars [8:4:2:1] with Fig. 6 live.
int million_rows(const BenchArgs& args, RuntimeTable& table) {
  const std::string threads = threads_text(args);
  RuntimeRow r;
  const uint32_t size = args.size == 10 ? 100 : args.size;
  print_runtime_header("bench million: " + std::to_string(size) + "^3 cube, " + std::to_string(args.steps) +
                       " steps, random_vars [8:4:2:1] + Fig. 6 live, distributed, " + threads);
  const uint64_t modules = uint64_t{size} * size * size;
  auto ensemble = [&](uint32_t n) { return million_toml(n, args.detector); };
  // The same run on 10^3 modules first: what a PatternMatcher costs when everything is in cache.
  RuntimeRow small;
  if (!print_runtime_row("8:4:2:1, 10^3 modules", ensemble(10), args, std::max(args.repeat, 5), table, small)) return 1;
  if (!print_runtime_row("8:4:2:1", ensemble(size), args, args.repeat, table, r)) return 1;
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

// The rows of table1, overhead or million.
int run_rows(const BenchArgs& args, RuntimeTable& table) {
  if (args.name == "table1") return table1_rows(args, table);
  if (args.name == "overhead") return overhead_rows(args, table);
  return million_rows(args, table);
}

}  // namespace

}  // namespace dw::bench
