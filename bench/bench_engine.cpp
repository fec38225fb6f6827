// `dwatch bench engine`: Table I on the watch engine alone: a 10x10x10 cubic lattice, 100 steps,
// the Fig. 6 watchpoint, x_i uniform in 0..max_i-1 for each tuple, both algorithms. Each row runs
// in a child process so that its peak memory is its own.
#include <iomanip>
#include <iostream>

#include "bench/bench.h"
#include "bench/bench_child.h"
#include "shell/output_files.h"

namespace dw::bench {

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

}  // namespace dw::bench
