// `dwatch bench expressions`: what docs/design.md §4b's expressions cost the engine, beside the plain
// Fig. 6 row on the same Table I ensemble (default [2:2:2:2]), both algorithms:
//   plain       Fig. 6 as the paper writes it
//   arithmetic  Fig. 6 written with arithmetic, each term still an own leaf of its slot
//   aggregate   modules(a); count(n in neighbors(a): n.x1 = 0) >= 3, one slot over its neighbours
// Each row is the fastest of --repeat runs in a child process (peak memory its own), as `engine`.
#include <iomanip>
#include <iostream>

#include "bench/bench.h"
#include "bench/bench_child.h"
#include "shell/output_files.h"

namespace dw::bench {

int bench_expressions(const BenchArgs& args, bool tuples_given) {
  const std::pair<const char*, const char*> forms[] = {
      {"plain", kFig6},
      {"arithmetic", "modules(a b c d); (a.x1 + 0 = 0) and (b.x2 * 1 = 0) and (c.x3 - 0 = 0) and (d.x4 = 0 + 0)"},
      {"aggregate", "modules(a); count(n in neighbors(a): n.x1 = 0) >= 3"},
  };
  std::vector<watch::Algorithm> algorithms;
  if (args.algorithm != "distributed") algorithms.push_back(watch::Algorithm::Centralized);
  if (args.algorithm != "centralized") algorithms.push_back(watch::Algorithm::Distributed);
  std::unique_ptr<sim::OutputFile> csv_file;
  if (!open_csv(args, "expressions", "tuple,algorithm,form,matches,created,best_seconds,median_seconds,ratio_to_plain",
                csv_file))
    return 2;
  std::cout << "bench expressions: " << args.size << "^3 cubic lattice, " << args.steps
            << " steps; each form beside plain Fig. 6\n";
  std::cout << std::left << std::setw(11) << "tuple" << std::setw(13) << "algorithm" << std::setw(12) << "form"
            << std::right << std::setw(12) << "matches" << std::setw(14) << "created" << std::setw(10) << "best s"
            << std::setw(10) << "median s" << std::setw(10) << "x plain\n";
  const std::vector<std::string> tuples = tuples_given ? args.tuples : std::vector<std::string>{"2:2:2:2"};
  for (const std::string& tuple_text : tuples) {
    const std::optional<sim::Trace> trace = table1_trace(args, tuple_text);
    if (!trace) return 2;
    for (watch::Algorithm a : algorithms) {
      double plain = 0;
      for (const auto& [form, text] : forms) {
        auto compiled = watch::compile_watchpoint(form, watch::SourceText(form, text));
        const watch::Watchpoint& w = std::get<watch::Watchpoint>(compiled);
        EngineRow row;
        if (!in_child([&] { return run_engine_row(*trace, w, a, args.detector.options(), args.repeat); }, row,
                      row.peak_kib)) {
          std::cerr << "dwatch bench: error: the benchmark run failed\n";
          return 1;
        }
        if (plain == 0) plain = row.seconds;
        const double ratio = plain > 0 ? row.seconds / plain : 0;
        std::cout << std::left << std::setw(11) << tuple_text << std::setw(13) << watch::algorithm_name(a)
                  << std::setw(12) << form << std::right << std::setw(12) << row.matches << std::setw(14) << row.created
                  << std::setw(10) << std::fixed << std::setprecision(4) << row.seconds << std::setw(10)
                  << row.median_seconds << std::setw(9) << std::setprecision(2) << ratio << "\n";
        if (csv_file)
          csv_file->stream() << tuple_text << "," << watch::algorithm_name(a) << "," << form << "," << row.matches
                             << "," << row.created << "," << row.seconds << "," << row.median_seconds << "," << ratio
                             << "\n";
      }
    }
  }
  return shell::commit_outputs({csv_file.get()}) ? 0 : 1;
}

}  // namespace dw::bench
