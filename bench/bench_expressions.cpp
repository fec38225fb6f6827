// `dwatch bench expressions`: what docs/design.md §4b's expressions and §4c's windows cost the
// engine, each beside the form it is compared with (its peer), on the same Table I ensemble
// (default [2:2:2:2]), both algorithms:
//   plain       Fig. 6 as the paper writes it
//   arithmetic  Fig. 6 written with arithmetic, each term still an own leaf of its slot (peer: plain)
//   aggregate   modules(a); count(n in neighbors(a): n.x1 = 0) >= 3, one slot over its neighbours
//               (peer: plain)
//   one slot    modules(a); a.x1 = 0
//   once[1000]  modules(a); once[1000](a.x1 = 0), a window each module keeps (peer: one slot;
//               issue 61's bar: at most 1.5x its time and 200 bytes a module more)
// Each row is the fastest of --repeat runs in a child process (peak memory its own), as `engine`.
#include <iomanip>
#include <iostream>

#include "bench/bench.h"
#include "bench/bench_child.h"
#include "shell/output_files.h"

namespace dw::bench {

int bench_expressions(const BenchArgs& args, bool tuples_given) {
  struct Form {
    const char* name;
    const char* text;
    int peer;  // the row it is compared with (itself for a peer)
  };
  const Form forms[] = {
      {"plain", kFig6, 0},
      {"arithmetic", "modules(a b c d); (a.x1 + 0 = 0) and (b.x2 * 1 = 0) and (c.x3 - 0 = 0) and (d.x4 = 0 + 0)", 0},
      {"aggregate", "modules(a); count(n in neighbors(a): n.x1 = 0) >= 3", 0},
      {"one slot", "modules(a); a.x1 = 0", 3},
      {"once[1000]", "modules(a); once[1000](a.x1 = 0)", 3},
  };
  const double modules = double(args.size) * double(args.size) * double(args.size);
  std::vector<watch::Algorithm> algorithms;
  if (args.algorithm != "distributed") algorithms.push_back(watch::Algorithm::Centralized);
  if (args.algorithm != "centralized") algorithms.push_back(watch::Algorithm::Distributed);
  std::unique_ptr<sim::OutputFile> csv_file;
  if (!open_csv(args, "expressions",
                "tuple,algorithm,form,peer,matches,created,best_seconds,median_seconds,ratio_to_peer,peak_kib,"
                "bytes_a_module_over_peer",
                csv_file))
    return 2;
  std::cout << "bench expressions: " << args.size << "^3 cubic lattice, " << args.steps
            << " steps; each form beside its peer (x peer: time; B/module: peak memory over the peer's)\n";
  std::cout << std::left << std::setw(11) << "tuple" << std::setw(13) << "algorithm" << std::setw(12) << "form"
            << std::setw(10) << "peer" << std::right << std::setw(12) << "matches" << std::setw(14) << "created"
            << std::setw(10) << "best s" << std::setw(10) << "median s" << std::setw(8) << "x peer" << std::setw(10)
            << "peak MiB" << std::setw(10) << "B/module\n";
  const std::vector<std::string> tuples = tuples_given ? args.tuples : std::vector<std::string>{"2:2:2:2"};
  for (const std::string& tuple_text : tuples) {
    const std::optional<sim::Trace> trace = table1_trace(args, tuple_text);
    if (!trace) return 2;
    for (watch::Algorithm a : algorithms) {
      std::vector<EngineRow> rows;
      for (const Form& form : forms) {
        auto compiled = watch::compile_watchpoint(form.name, watch::SourceText(form.name, form.text));
        const watch::Watchpoint& w = std::get<watch::Watchpoint>(compiled);
        EngineRow& row = rows.emplace_back();
        if (!in_child([&] { return run_engine_row(*trace, w, a, args.detector.options(), args.repeat); }, row,
                      row.peak_kib)) {
          std::cerr << "dwatch bench: error: the benchmark run failed\n";
          return 1;
        }
        const EngineRow& peer = rows[size_t(form.peer)];
        const double ratio = peer.seconds > 0 ? row.seconds / peer.seconds : 0;
        const double over = (double(row.peak_kib) - double(peer.peak_kib)) * 1024.0 / modules;
        std::cout << std::left << std::setw(11) << tuple_text << std::setw(13) << watch::algorithm_name(a)
                  << std::setw(12) << form.name << std::setw(10) << forms[form.peer].name << std::right << std::setw(12)
                  << row.matches << std::setw(14) << row.created << std::setw(10) << std::fixed << std::setprecision(4)
                  << row.seconds << std::setw(10) << row.median_seconds << std::setw(8) << std::setprecision(2) << ratio
                  << std::setw(10) << std::setprecision(1) << double(row.peak_kib) / 1024.0 << std::setw(10)
                  << std::setprecision(0) << over << "\n";
        if (csv_file)
          csv_file->stream() << tuple_text << "," << watch::algorithm_name(a) << "," << form.name << ","
                             << forms[form.peer].name << "," << row.matches << "," << row.created << "," << row.seconds
                             << "," << row.median_seconds << "," << ratio << "," << row.peak_kib << "," << over << "\n";
      }
    }
  }
  return shell::commit_outputs({csv_file.get()}) ? 0 : 1;
}

}  // namespace dw::bench
