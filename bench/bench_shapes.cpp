// `dwatch bench shapes`: every group shape and state mode (docs/design.md §4a) on the watch engine, over
// the Table I ensemble (a 10x10x10 cube, 100 steps, the Fig. 6 watchpoint, default [2:2:2:2]):
// time, and messages per match, which is the price of exactness beside the paper's algorithm.
#include <iomanip>
#include <iostream>

#include "bench/bench.h"
#include "bench/bench_child.h"
#include "shell/output_files.h"

namespace dw::bench {
namespace {

struct Reading {
  const char* name;
  watch::Algorithm algorithm;
  watch::GroupShape shape;
  watch::States states;
};

constexpr Reading kReadings[] = {
    {"centralized chain", watch::Algorithm::Centralized, watch::GroupShape::Chain, watch::States::Simultaneous},
    {"centralized ordered", watch::Algorithm::Centralized, watch::GroupShape::Ordered, watch::States::Simultaneous},
    {"centralized any", watch::Algorithm::Centralized, watch::GroupShape::Any, watch::States::Simultaneous},
    {"distributed consistent chain", watch::Algorithm::Distributed, watch::GroupShape::Chain,
     watch::States::Consistent},
    {"distributed simultaneous chain", watch::Algorithm::Distributed, watch::GroupShape::Chain,
     watch::States::Simultaneous},
    {"distributed simultaneous ordered", watch::Algorithm::Distributed, watch::GroupShape::Ordered,
     watch::States::Simultaneous},
    {"distributed simultaneous any", watch::Algorithm::Distributed, watch::GroupShape::Any,
     watch::States::Simultaneous},
};

}  // namespace

int bench_shapes(const BenchArgs& args, bool tuples_given) {
  auto compiled = watch::compile_watchpoint("fig6", watch::SourceText("fig6", kFig6));
  const watch::Watchpoint& w = std::get<watch::Watchpoint>(compiled);
  const std::vector<std::string> tuples = tuples_given ? args.tuples : std::vector<std::string>{"2:2:2:2"};
  std::unique_ptr<sim::OutputFile> csv_file;
  if (!open_csv(args, "shapes",
                "tuple,reading,algorithm,shape,states,matches,created,messages,lost,messages_per_match,best_seconds,"
                "median_seconds,peak_mib",
                csv_file))
    return 2;
  std::cout << "bench shapes: " << args.size << "^3 cubic lattice, " << args.steps
            << " steps, Fig. 6 watchpoint, 1 thread; best and median of " << args.repeat << "\n";
  std::cout << std::left << std::setw(9) << "tuple" << std::setw(34) << "reading" << std::right << std::setw(11)
            << "matches" << std::setw(12) << "created" << std::setw(12) << "messages" << std::setw(7) << "lost"
            << std::setw(10) << "msg/match" << std::setw(9) << "best s" << std::setw(10) << "median s" << std::setw(10)
            << "peak MiB\n";
  int status = 0;
  for (const std::string& tuple_text : tuples) {
    const std::optional<sim::Trace> made = table1_trace(args, tuple_text);
    if (!made) return 2;
    const sim::Trace& trace = *made;
    std::vector<EngineRow> rows;
    for (const Reading& r : kReadings) {
      watch::DetectorOptions o = args.detector.options();
      o.shape = r.shape;
      if (r.algorithm == watch::Algorithm::Distributed) o.states = r.states;
      EngineRow row;
      if (!in_child([&] { return run_engine_row(trace, w, r.algorithm, o, args.repeat); }, row, row.peak_kib)) {
        std::cerr << "dwatch bench: error: the benchmark run failed\n";
        return 1;
      }
      rows.push_back(row);
      const double mib = static_cast<double>(row.peak_kib) / 1024.0;
      const double per_match = row.matches ? static_cast<double>(row.messages) / static_cast<double>(row.matches) : 0;
      std::cout << std::left << std::setw(9) << tuple_text << std::setw(34) << r.name << std::right << std::setw(11)
                << row.matches << std::setw(12) << row.created << std::setw(12) << row.messages << std::setw(7)
                << row.lost << std::setw(10) << std::fixed << std::setprecision(2) << per_match << std::setw(9)
                << std::setprecision(3) << row.seconds << std::setw(10) << row.median_seconds << std::setw(10)
                << std::setprecision(1) << mib << (row.stopped ? "  stopped at the budget" : "") << "\n";
      if (csv_file)
        csv_file->stream() << tuple_text << "," << r.name << "," << watch::algorithm_name(r.algorithm) << ","
                           << watch::shape_name(r.shape) << ","
                           << (r.algorithm == watch::Algorithm::Distributed ? watch::states_name(r.states) : "") << ","
                           << row.matches << "," << row.created << "," << row.messages << "," << row.lost << ","
                           << per_match << "," << row.seconds << "," << row.median_seconds << "," << mib << "\n";
      if (row.stopped) status = 1;
    }
    // The bars of issue 14, by the fastest runs.
    auto ratio = [&](size_t a, size_t b) { return rows[a].seconds / std::max(rows[b].seconds, 1e-9); };
    std::cout << std::setprecision(2) << "  simultaneous chain / consistent chain: " << ratio(4, 3)
              << "x;  simultaneous any / centralized any: " << ratio(6, 2)
              << "x;  centralized any: " << std::setprecision(3) << rows[2].seconds << " s\n";
  }
  if (!shell::commit_outputs({csv_file.get()})) return 1;
  return status;
}

}  // namespace dw::bench
