// `dwatch bench NAME`: reproductions of the paper's measurements.
//
//   engine   Table I on the watch engine alone: a 10x10x10 cubic lattice, 100 steps, the Fig. 6
//            watchpoint, x_i uniform in 0..max_i-1 for each tuple, both algorithms. Each row runs
//            in a child process so that its peak memory is its own.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "app/bench.h"
#include "app/bench_child.h"
#include "app/commands.h"
#include "app/detector_flags.h"
#include "shell/integer_option.h"
#include "shell/output_files.h"
#include "sim/rank_exchange.h"
#include "sim/synthetic_trace.h"
#include "watch/make_detector.h"

namespace dw::app {

std::vector<int64_t> parse_tuple(const std::string& text) {
  std::vector<int64_t> out;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, ':');) {
    size_t used = 0;
    long long v = 0;
    try {
      v = std::stoll(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != part.size() || v < 1) return {};
    out.push_back(v);
  }
  return out.size() == 4 ? out : std::vector<int64_t>{};
}

std::optional<sim::Trace> table1_trace(const BenchArgs& args, const std::string& tuple_text) {
  sim::CubicRandomVars spec;
  spec.maxima = parse_tuple(tuple_text);
  if (spec.maxima.empty()) {
    std::cerr << "dwatch bench: error: tuple '" << tuple_text << "' is not four positive integers like 2:2:2:2\n";
    return std::nullopt;
  }
  spec.nx = spec.ny = spec.nz = args.size;
  spec.steps = args.steps;
  spec.seed = args.seed;
  return sim::make_cubic_random_vars(spec);
}

namespace {

// Runs a fresh detector over every frame `repeat` times (and drains it); the frames are built
// before timing.
EngineRow engine_row(const sim::Trace& trace, const watch::Watchpoint& w, watch::Algorithm a,
                     const watch::DetectorOptions& o, int repeat, const MatchSink* on_match) {
  EngineRow row;
  auto reader = std::get<sim::FrameReader>(sim::FrameReader::make(trace, std::nullopt, sim::default_frame_budget()));
  std::vector<sim::FrameBuffer> buffers(static_cast<size_t>(trace.step_count()));
  std::vector<watch::Frame> frames;
  for (int64_t s = 0; s < trace.step_count(); ++s) frames.push_back(reader.frame(s, buffers[size_t(s)]));
  const size_t slots = w.program.slots.size();
  std::vector<double> times;
  for (int r = 0; r < repeat; ++r) {
    uint64_t matches = 0;
    auto detector =
        watch::make_detector(a, w, reader.universe(), o,
                             [&](int64_t step, std::span<const watch::ModuleId> ids, std::span<const watch::Value>) {
                               matches += ids.size() / slots;
                               if (on_match) (*on_match)(step, ids);
                             });
    const auto start = std::chrono::steady_clock::now();
    for (const watch::Frame& f : frames) detector->observe(f);
    detector->finish();
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    const watch::DetectorStats& st = detector->stats();
    row.matches = matches;
    row.created = st.created;
    row.messages = st.messages;
    row.lost = st.lost;
    row.peak_live = st.peak_live;
    row.stopped = st.stopped;
    for (size_t i = 0; i < st.created_by_filled.size() && i < 5; ++i) row.by_filled[i] = st.created_by_filled[i];
  }
  std::sort(times.begin(), times.end());
  row.seconds = times.front();
  row.median_seconds = times[times.size() / 2];
  return row;
}

}  // namespace

EngineRow run_engine_row(const sim::Trace& trace, const watch::Watchpoint& w, watch::Algorithm a,
                         const watch::DetectorOptions& o, int repeat) {
  return engine_row(trace, w, a, o, repeat, nullptr);
}

EngineRow count_engine_row(const sim::Trace& trace, const watch::Watchpoint& w, watch::Algorithm a,
                           const watch::DetectorOptions& o, const MatchSink& on_match) {
  return engine_row(trace, w, a, o, 1, on_match ? &on_match : nullptr);
}

int bench_engine(const BenchArgs& args) {
  auto compiled = watch::compile_watchpoint("fig6", watch::SourceText("fig6", kFig6));
  const watch::Watchpoint& w = std::get<watch::Watchpoint>(compiled);
  std::vector<watch::Algorithm> algorithms;
  if (args.algorithm != "distributed") algorithms.push_back(watch::Algorithm::Centralized);
  if (args.algorithm != "centralized") algorithms.push_back(watch::Algorithm::Distributed);

  std::unique_ptr<sim::OutputFile> csv_file;
  if (!open_csv(args, "engine",
                "tuple,algorithm,matches,created,messages,peak_live,best_seconds,median_seconds,peak_mib,"
                "filled1,filled2,filled3,filled4",
                csv_file))
    return 2;
  std::cout << "bench engine: " << args.size << "^3 cubic lattice, " << args.steps << " steps, Fig. 6 watchpoint\n";
  std::cout << std::left << std::setw(11) << "tuple" << std::setw(13) << "algorithm" << std::right << std::setw(12)
            << "matches" << std::setw(14) << "created" << std::setw(12) << "peak live" << std::setw(10) << "best s"
            << std::setw(10) << "median s" << std::setw(11) << "peak MiB"
            << "   by slots filled (Fig. 7)\n";
  int status = 0;
  for (const std::string& tuple_text : args.tuples) {
    const std::optional<sim::Trace> made = table1_trace(args, tuple_text);
    if (!made) return 2;
    const sim::Trace& trace = *made;
    if (!args.write_trace.empty()) {
      if (std::string error = sim::write_trace(trace, args.write_trace); !error.empty()) {
        std::cerr << "dwatch: error: " << error << "\n";
        return 1;
      }
      std::cout << "wrote " << args.write_trace << " (" << trace.line_count() << " lines, tuple " << tuple_text
                << ")\n";
    }
    for (watch::Algorithm a : algorithms) {
      EngineRow row;
      if (!in_child([&] { return run_engine_row(trace, w, a, args.detector.options(), args.repeat); }, row,
                    row.peak_kib)) {
        std::cerr << "dwatch bench: error: the benchmark run failed\n";
        return 1;
      }
      const double mib = static_cast<double>(row.peak_kib) / 1024.0;
      std::cout << std::left << std::setw(11) << tuple_text << std::setw(13) << watch::algorithm_name(a) << std::right
                << std::setw(12) << row.matches << std::setw(14) << row.created << std::setw(12) << row.peak_live
                << std::setw(10) << std::fixed << std::setprecision(3) << row.seconds << std::setw(10)
                << row.median_seconds << std::setw(11) << std::setprecision(1) << mib << "   ";
      for (int i = 1; i <= 4; ++i) std::cout << (i > 1 ? " " : "") << row.by_filled[i];
      std::cout << (row.stopped ? "  stopped at the budget" : "") << "\n";
      if (csv_file) {
        std::ostream& csv = csv_file->stream();
        csv << tuple_text << "," << watch::algorithm_name(a) << "," << row.matches << "," << row.created << ","
            << row.messages << "," << row.peak_live << "," << row.seconds << "," << row.median_seconds << "," << mib;
        for (int i = 1; i <= 4; ++i) csv << "," << row.by_filled[i];
        csv << "\n";
      }
      if (row.stopped) status = 1;
    }
  }
  if (!shell::commit_outputs({csv_file.get()})) return 1;
  return status;
}

bool open_csv(const BenchArgs& args, const std::string& name, const std::string& header,
              std::unique_ptr<sim::OutputFile>& out) {
  if (args.out_dir.empty()) return true;
  std::error_code ec;
  std::filesystem::create_directories(args.out_dir, ec);
  if (ec) {
    std::cerr << "dwatch: error: --out: cannot make " << args.out_dir << ": " << ec.message() << "\n";
    return false;
  }
  if (!shell::open_output({"--out", (std::filesystem::path(args.out_dir) / (name + ".csv")).string()}, out))
    return false;
  out->stream() << header << "\n";
  return true;
}

void add_bench_command(CLI::App& app, std::function<int()>& run) {
  auto* cmd = app.add_subcommand("bench",
                                 "Reproduce the paper's measurements: paper (all of §V, with plots), engine, table1, "
                                 "overhead, million; expressions, shapes, "
                                 "mpi, physics, render, session, view, lua");
  auto args = std::make_shared<BenchArgs>();
  cmd->add_option("name", args->name, "Benchmark to run")
      ->required()
      ->check(CLI::IsMember({"engine", "expressions", "shapes", "table1", "overhead", "million", "mpi", "physics",
                             "paper", "render", "session", "view", "lua"}));
  cmd->add_option("--tuple", args->tuples, "Host-program tuples max_x1:max_x2:max_x3:max_x4 (repeatable)");
  cmd->add_option("--which", args->algorithm, "centralized, distributed or both")
      ->check(CLI::IsMember({"centralized", "distributed", "both"}));
  shell::add_integer_option(*cmd, "--size", args->size, {"size", 1, 200},
                            "Lattice edge (modules per side; million: 100)");
  shell::add_integer_option(*cmd, "--steps", args->steps, {"steps", 1, 1'000'000}, "Steps to run");
  shell::add_integer_option(*cmd, "--seed", args->seed, scenarios::kSeedRange,
                            "Seed of the host program's random variables");
  cmd->add_option("--out", args->out_dir, "Write NAME.csv into this directory");
  shell::add_integer_option(*cmd, "--threads,-j", args->threads, scenarios::kThreadsRange,
                            "Threads stepping modules (table1, overhead, million)");
  shell::add_integer_option(*cmd, "--repeat", args->repeat, {"repeat", 1, 100},
                            "Runs per row (paper: passes over all the rows); the fastest and the median are reported");
  cmd->add_flag("--quick", args->quick,
                "paper: at most 2 passes, 4 sizes for Fig. 8 (under a minute); lua: the memory row at 50^3");
  cmd->add_option("--table2-workload", args->table2_workload,
                  "paper: Table II's baseline, random_vars alone (the default) or with aggregation_routing")
      ->check(CLI::IsMember({"random_vars", "aggregation_routing"}));
  cmd->add_option("--partition", args->partition, "mpi: how the ranks share the modules (run --partition)")
      ->check(CLI::IsMember(std::vector<std::string>(sim::kPartitionNames.begin(), sim::kPartitionNames.end())));
  cmd->add_option("--write-trace", args->write_trace, "Also write the synthetic trace (wptrace v1) to FILE");
  add_detector_flags(*cmd, args->detector, /*with_algorithm=*/false);
  cmd->callback([&run, args, cmd] {
    const bool tuples_given = cmd->count("--tuple") > 0;
    run = [args, tuples_given] {
      if (args->name == "engine") return bench_engine(*args);
      if (args->name == "shapes") return bench_shapes(*args, tuples_given);
      if (args->name == "expressions") return bench_expressions(*args, tuples_given);
      if (args->name == "paper") return bench_paper(*args);
      if (args->name == "render") return bench_render(*args);
      if (args->name == "session") return bench_session(*args);
      if (args->name == "view") return bench_view(*args);
      if (args->name == "lua") return bench_lua(*args);
      if (args->name == "mpi") return bench_mpi(*args);
      return bench_runtime(*args);
    };
  });
}

}  // namespace dw::app
