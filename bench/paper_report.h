// What `dwatch bench paper` measured, and what it makes of it: the CSV files, the fits, the
// verdict on each of the paper's claims, and paper.md. Every derived figure (an overhead, a fit, a
// ratio to the paper) is computed here once, for the files and the console alike.
#pragma once

#include <array>
#include <cstdint>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "bench/bench.h"
#include "bench/paper_numbers.h"

namespace dw::bench {

// Least squares y = slope * x + intercept; r_squared = 1 - SS_res / SS_tot (1 when every y is
// the same and the line goes through them all).
struct LinearFit {
  double slope = 0, intercept = 0, r_squared = 0;
  double at(double x) const { return slope * x + intercept; }
};
LinearFit fit_line(std::span<const double> x, std::span<const double> y);

struct PaperTable1Row {
  std::string tuple;
  RuntimeRow live;                     // random_vars + Fig. 6, distributed, live: the timed row
  EngineRow distributed, centralized;  // the engine over the same ensemble's trace: Fig. 7's counts
  uint64_t chain_sets = 0;             // distinct module sets among the distributed matches, per step
  uint64_t groups_matched = 0;         // connected 4-module groups matched, each once (shape any)
  double one_per_group = 0;            // expected matches if each connected group counted once, one order
};

enum Fig8Series { kNoWatch, kCentralized, kDistributed, kFig8Series };
struct Fig8Row {
  uint32_t planes = 0, modules = 0;
  std::array<RuntimeRow, kFig8Series> runs;
};

struct PaperRun {
  BenchArgs args;  // as run (repeat after --quick)
  std::string date, cpu, version;
  unsigned cores = 0;
  double load_average = 0;       // over the last minute, at the start
  uint64_t groups_per_step = 0;  // connected 4-module groups of the Table I lattice
  std::vector<PaperTable1Row> table1;
  std::vector<Fig8Row> fig8;
  std::array<RuntimeRow, paper::kFrequencies.size()> table2_baseline;
  std::array<std::array<RuntimeRow, paper::kFrequencies.size()>, paper::kTable2Sizes> table2;
};

// How long a timed row's runs add up to at least: the best of many for rows of a few milliseconds.
inline double paper_min_seconds(const BenchArgs& args) { return args.quick ? 0.1 : 0.3; }

const char* fig8_series_name(int series);
// Fig. 8: seconds against modules, one series.
LinearFit fig8_fit(const PaperRun& run, int series);
// Fig. 8: the watch's overhead in percent over the run without it, averaged over the sizes.
double fig8_mean_overhead(const PaperRun& run, int series);
// Table II: the overhead in percent of expression size `size` (1..5) at a frequency.
double table2_overhead(const PaperRun& run, int size, size_t frequency);

// One of the paper's claims, checked against this run.
struct Verdict {
  std::string claim, paper, measured, criterion;
  bool holds = false;
};
std::vector<Verdict> verdicts(const PaperRun& run);

// The CSV files the plots are made from (scripts/plot_paper.py reads them by these columns).
void write_table1_csv(const PaperRun& run, std::ostream& out);
void write_fig7_csv(const PaperRun& run, std::ostream& out);
void write_fig8_csv(const PaperRun& run, std::ostream& out);
void write_table2_csv(const PaperRun& run, std::ostream& out);
// paper.md: every number beside the paper's, the machine, the commands, the verdicts.
std::string paper_markdown(const PaperRun& run, const std::vector<Verdict>& judged);
// Where the files go: --out, or ./paper.
std::string out_dir(const BenchArgs& args);
// The command line that reproduces `run`, and the one that redraws its plots.
std::string paper_command(const PaperRun& run);
// `script` is scripts/plot_paper.py where this program finds it (shipped_files.h).
std::string plot_command(const std::string& dir, const std::string& script);

}  // namespace dw::bench
