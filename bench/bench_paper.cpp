// `dwatch bench paper`: the paper's whole evaluation (§V) regenerated on this machine: Table I,
// Fig. 7, Fig. 8 and Table II, measured here, then handed to paper_report.cpp for the CSV files,
// the verdicts and paper.md, and to scripts/plot_paper.py for the plots.
#include <sys/utsname.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <thread>

#include "bench/bench.h"
#include "bench/paper_report.h"
#include "bench/shipped_files.h"
#include "shell/output_files.h"
#include "watch/connected_groups.h"

namespace dw::bench {
namespace {

// Counts the distinct module sets among a detector's four-slot matches, step by step: a set
// matched by several bindings (orders of its modules) at one step counts once.
class DistinctSets {
 public:
  void add(int64_t step, std::span<const watch::ModuleId> ids) {
    std::vector<Set>& at = pending_[step];
    for (size_t i = 0; i + 4 <= ids.size(); i += 4) {
      Set s{ids[i], ids[i + 1], ids[i + 2], ids[i + 3]};
      std::sort(s.begin(), s.end());
      if (at.empty() || at.back() != s) at.push_back(s);  // a group's bindings often come together
    }
    // Matches arrive in step order, give or take a detector's lag: settle the steps long past.
    while (pending_.size() > 1 && pending_.begin()->first + kSettle < step) settle(pending_.begin());
  }
  uint64_t finish() {
    while (!pending_.empty()) settle(pending_.begin());
    return count_;
  }

 private:
  using Set = std::array<watch::ModuleId, 4>;
  static constexpr int64_t kSettle = 64;
  void settle(std::map<int64_t, std::vector<Set>>::iterator it) {
    std::vector<Set>& sets = it->second;
    std::sort(sets.begin(), sets.end());
    count_ += static_cast<uint64_t>(std::unique(sets.begin(), sets.end()) - sets.begin());
    pending_.erase(it);
  }
  std::map<int64_t, std::vector<Set>> pending_;
  uint64_t count_ = 0;
};

// The connected groups of four modules in a trace's first step (its lattice).
uint64_t connected_groups(const sim::Trace& trace) {
  auto reader = std::get<sim::FrameReader>(sim::FrameReader::make(trace, std::nullopt, sim::default_frame_budget()));
  sim::FrameBuffer buffer;
  const watch::Frame f = reader.frame(0, buffer);
  watch::StepHistory::Graph graph{
      {f.present.begin(), f.present.end()}, {f.nbr_begin.begin(), f.nbr_begin.end()}, {f.nbrs.begin(), f.nbrs.end()}};
  watch::ConnectedGroups groups(static_cast<uint32_t>(f.present.size()));
  uint64_t n = 0;
  groups.enumerate(graph, graph.present, 4, [&](std::span<const uint32_t>) { return ++n, true; });
  return n;
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  utsname u{};
  return uname(&u) == 0 ? u.machine : "unknown";
}

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%d %H:%M UTC", &tm);
  return text;
}

// A row to time, and where its figures go.
struct TimedJob {
  std::string toml;
  RuntimeRow* row;
};

// Times every job in passes: each pass runs every row once (the best of runs adding up to
// paper_min_seconds), and a row keeps its fastest pass. A burst of load from elsewhere then
// slows one pass of many rows, not every run of one row, which best-of-N in a row cannot undo.
bool time_jobs(const PaperRun& run, const std::vector<TimedJob>& jobs) {
  const int passes = run.args.repeat;
  std::vector<std::vector<double>> bests(jobs.size());
  const bool terminal = isatty(STDOUT_FILENO);  // a progress line, rewritten in place
  for (int pass = 0; pass < passes; ++pass) {
    std::cout << "  timing: pass " << pass + 1 << " of " << passes << " over " << jobs.size() << " rows"
              << (terminal ? "\r" : "\n") << std::flush;
    for (size_t j = 0; j < jobs.size(); ++j) {
      RuntimeRow r;
      if (!run_runtime_row(jobs[j].toml, run.args, 1, r, Timed::Steps, paper_min_seconds(run.args))) return false;
      if (pass == 0 || r.seconds < jobs[j].row->seconds) {
        const long peak = std::max(jobs[j].row->peak_kib, r.peak_kib);
        *jobs[j].row = r;
        jobs[j].row->peak_kib = peak;
      }
      bests[j].push_back(r.seconds);
    }
  }
  for (size_t j = 0; j < jobs.size(); ++j) {
    std::sort(bests[j].begin(), bests[j].end());
    jobs[j].row->median_seconds = bests[j][bests[j].size() / 2];
  }
  if (terminal) std::cout << std::string(60, ' ') << "\r";
  return true;
}

// The Fig. 8 sizes: every plane count 1..size, or four of them spread out (--quick).
std::vector<uint32_t> fig8_planes(const BenchArgs& args) {
  std::vector<uint32_t> planes;
  const uint32_t n = args.size;
  if (!args.quick || n <= 4) {
    for (uint32_t k = 1; k <= n; ++k) planes.push_back(k);
  } else {
    for (uint32_t i = 0; i < 4; ++i) planes.push_back(1 + (i * (n - 1) + 1) / 3);
  }
  return planes;
}

// The rows of every experiment, laid out in `run`, and the runs that time them:
//   Table I   random_vars + Fig. 6, distributed, per tuple;
//   Fig. 8    the medium-intensity workload on size x size x k stacked planes, without a watch,
//             with Fig. 6 centralized, with Fig. 6 distributed;
//   Table II  expressions of 1..5 slots, centralized, at three frequencies of x_i = 0, over a
//             baseline of random_vars (five variables at that frequency), with aggregation_routing
//             if asked.
std::vector<TimedJob> plan(PaperRun& run) {
  const BenchArgs& args = run.args;
  const std::string cube = cubic_toml(args.size, args.size, args.size);
  auto fig6 = [&](watch::Algorithm a) { return watch_toml("fig6", kFig6, a, args.detector); };
  const std::vector<uint32_t> planes = fig8_planes(args);
  run.table1.resize(args.tuples.size());
  run.fig8.resize(planes.size());
  std::vector<TimedJob> jobs;
  for (size_t i = 0; i < args.tuples.size(); ++i) {
    run.table1[i].tuple = args.tuples[i];
    jobs.push_back({cube + random_vars_toml(parse_tuple(args.tuples[i])) + fig6(watch::Algorithm::Distributed),
                    &run.table1[i].live});
  }
  const std::array<int64_t, 4> fig8_tuple{2, 2, 2, 2};
  for (size_t i = 0; i < run.fig8.size(); ++i) {
    Fig8Row& row = run.fig8[i];
    row.planes = planes[i];
    row.modules = args.size * args.size * row.planes;
    const std::string base =
        cubic_toml(args.size, args.size, row.planes) + kAggregationToml + random_vars_toml(fig8_tuple);
    jobs.push_back({base, &row.runs[kNoWatch]});
    jobs.push_back({base + fig6(watch::Algorithm::Centralized), &row.runs[kCentralized]});
    jobs.push_back({base + fig6(watch::Algorithm::Distributed), &row.runs[kDistributed]});
  }
  for (size_t f = 0; f < paper::kFrequencies.size(); ++f) {
    const std::vector<int64_t> maxima(paper::kTable2Sizes, paper::kFrequencies[f].max);
    std::string base = cube + random_vars_toml(maxima);
    if (args.table2_workload == "aggregation_routing") base += kAggregationToml;
    jobs.push_back({base, &run.table2_baseline[f]});
    for (int size = 1; size <= paper::kTable2Sizes; ++size)
      jobs.push_back({base + watch_toml("size" + std::to_string(size), conjunction_watch(size),
                                        watch::Algorithm::Centralized, args.detector),
                      &run.table2[size_t(size - 1)][f]});
  }
  return jobs;
}

// Table I's other counts and Fig. 7's: the engine over each tuple's ensemble, untimed.
bool count_table1(PaperRun& run, const watch::Watchpoint& fig6) {
  const BenchArgs& args = run.args;
  watch::DetectorOptions any = args.detector.options();
  any.shape = watch::GroupShape::Any;
  for (PaperTable1Row& row : run.table1) {
    const std::optional<sim::Trace> trace = table1_trace(args, row.tuple);
    if (!trace) return false;
    if (run.groups_per_step == 0) run.groups_per_step = connected_groups(*trace);
    DistinctSets chains, groups;
    row.distributed = count_engine_row(*trace, fig6, watch::Algorithm::Distributed, args.detector.options(),
                                       [&](int64_t t, std::span<const watch::ModuleId> ids) { chains.add(t, ids); });
    row.centralized = count_engine_row(*trace, fig6, watch::Algorithm::Centralized, args.detector.options(), {});
    count_engine_row(*trace, fig6, watch::Algorithm::Centralized, any,
                     [&](int64_t t, std::span<const watch::ModuleId> ids) { groups.add(t, ids); });
    row.chain_sets = chains.finish();
    row.groups_matched = groups.finish();
    double p = 1;
    for (int64_t m : parse_tuple(row.tuple)) p /= static_cast<double>(m);
    row.one_per_group = static_cast<double>(run.groups_per_step) * static_cast<double>(args.steps) * p;
    // The live run and the engine read the same ensemble: a difference would be a bug.
    if (row.live.matches != row.distributed.matches && !row.live.stopped && !row.distributed.stopped) {
      std::cerr << "dwatch bench: error: tuple " << row.tuple << ": the live run found " << row.live.matches
                << " matches, the engine over its trace " << row.distributed.matches << "\n";
      return false;
    }
  }
  return true;
}

void print_tables(const PaperRun& run) {
  const BenchArgs& args = run.args;
  const char* stopped = "  stopped at the --max-live budget";
  std::cout << "Table I: " << args.size << "^3 cube, " << args.steps << " steps, random_vars + Fig. 6, distributed\n"
            << std::left << std::setw(10) << "tuple" << std::right << std::setw(12) << "matches" << std::setw(10)
            << "best s" << std::setw(12) << "chain sets" << std::setw(12) << "groups" << std::setw(14)
            << "one per group" << std::setw(14) << "paper matches" << std::setw(9) << "paper s\n";
  for (const PaperTable1Row& row : run.table1) {
    std::cout << std::left << std::setw(10) << row.tuple << std::right << std::setw(12) << row.live.matches
              << std::setw(10) << std::fixed << std::setprecision(3) << row.live.seconds << std::setw(12)
              << row.chain_sets << std::setw(12) << row.groups_matched << std::setw(14) << std::setprecision(0)
              << row.one_per_group;
    if (const auto published = paper::table1(row.tuple))
      std::cout << std::setw(14) << published->matches << std::setw(8) << published->seconds;
    std::cout << (row.live.stopped ? stopped : "") << "\n";
  }

  std::cout << "Fig. 8: " << args.size << " x " << args.size
            << " stacked planes, aggregation_routing + random_vars [2:2:2:2], " << args.steps << " steps\n"
            << std::setw(8) << "modules" << std::setw(14) << "no watch s" << std::setw(15) << "centralized s"
            << std::setw(15) << "distributed s\n";
  for (const Fig8Row& row : run.fig8) {
    std::cout << std::setw(8) << row.modules << std::fixed << std::setprecision(4);
    for (const RuntimeRow& r : row.runs) std::cout << std::setw(14) << r.seconds << (r.stopped ? "*" : " ");
    std::cout << "\n";
  }

  std::cout << "Table II: " << args.size << "^3 cube, " << args.steps << " steps, centralized, baseline "
            << args.table2_workload << "; overhead in percent (the paper's in brackets)\n"
            << std::setw(5) << "size";
  for (const paper::Frequency& f : paper::kFrequencies) std::cout << std::setw(22) << f.name;
  std::cout << "\n";
  for (int size = 1; size <= paper::kTable2Sizes; ++size) {
    std::cout << std::setw(5) << size;
    for (size_t f = 0; f < paper::kFrequencies.size(); ++f) {
      std::ostringstream cell;
      cell << std::fixed << std::setprecision(1) << table2_overhead(run, size, f) << " [" << paper::kTable2[size - 1][f]
           << "]" << (run.table2[size_t(size - 1)][f].stopped ? "*" : "");
      std::cout << std::setw(22) << cell.str();
    }
    std::cout << "\n";
  }
}

bool any_stopped(const PaperRun& run) {
  bool stopped = false;
  for (const PaperTable1Row& r : run.table1) stopped |= r.live.stopped || r.distributed.stopped;
  for (const Fig8Row& r : run.fig8)
    for (const RuntimeRow& x : r.runs) stopped |= x.stopped;
  for (const auto& size : run.table2)
    for (const RuntimeRow& x : size) stopped |= x.stopped;
  return stopped;
}

}  // namespace

std::string conjunction_watch(int size) {
  std::string slots, formula;
  for (int i = 1; i <= size; ++i) {
    const std::string s = "s" + std::to_string(i);
    slots += (i > 1 ? " " : "") + s;
    formula += (i > 1 ? " and " : "") + ("(" + s + ".x" + std::to_string(i) + " = 0)");
  }
  return "modules(" + slots + "); " + formula;
}

int bench_paper(const BenchArgs& given) {
  for (const std::string& tuple : given.tuples)
    if (parse_tuple(tuple).empty()) {
      std::cerr << "dwatch bench: error: tuple '" << tuple << "' is not four positive integers like 2:2:2:2\n";
      return 2;
    }
  PaperRun run;
  run.args = given;
  if (run.args.quick) run.args.repeat = std::min(run.args.repeat, 2);
  run.date = utc_now();
  run.cpu = cpu_model();
  run.cores = std::thread::hardware_concurrency();
  run.version = DWATCH_VERSION;
  double load[1] = {0};
  if (getloadavg(load, 1) == 1) run.load_average = load[0];
  const std::string dir = out_dir(run.args);

  // The outputs are opened first, so that a bad --out costs nothing.
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    std::cerr << "dwatch: error: --out: cannot make " << dir << ": " << ec.message() << "\n";
    return 2;
  }
  constexpr std::array<const char*, 5> kFiles{"table1.csv", "fig7.csv", "fig8.csv", "table2.csv", "paper.md"};
  std::array<std::unique_ptr<sim::OutputFile>, kFiles.size()> files;
  for (size_t i = 0; i < kFiles.size(); ++i)
    if (!shell::open_output({"--out", (std::filesystem::path(dir) / kFiles[i]).string()}, files[i])) return 2;

  std::cout << "bench paper: the paper's §V on " << run.cpu << " (" << run.cores << " cores, load average "
            << std::fixed << std::setprecision(2) << run.load_average << "), every row timed in " << run.args.repeat
            << (run.args.repeat == 1 ? " pass" : " passes") << ", its fastest kept; writing " << dir << "/\n";
  const auto start = std::chrono::steady_clock::now();
  auto compiled = watch::compile_watchpoint("fig6", watch::SourceText("fig6", kFig6));
  const std::vector<TimedJob> jobs = plan(run);
  if (!time_jobs(run, jobs) || !count_table1(run, std::get<watch::Watchpoint>(compiled))) return 1;
  print_tables(run);

  const std::vector<Verdict> judged = verdicts(run);
  std::cout << "The paper's claims:\n";
  for (const Verdict& v : judged)
    std::cout << "  " << (v.holds ? "holds:         " : "does not hold: ") << v.claim << ": " << v.measured << "\n";
  write_table1_csv(run, files[0]->stream());
  write_fig7_csv(run, files[1]->stream());
  write_fig8_csv(run, files[2]->stream());
  write_table2_csv(run, files[3]->stream());
  files[4]->stream() << paper_markdown(run, judged);
  if (!shell::commit_outputs({files[0].get(), files[1].get(), files[2].get(), files[3].get(), files[4].get()}))
    return 1;

  const std::string plot = plot_command(dir, shipped_files().plot_script);
  if (std::system((plot + " >&2").c_str()) != 0) {
    std::cerr << "dwatch bench: error: the plots were not made (" << plot
              << "); the CSV files and paper.md are written. Plotting needs Debian's python3-matplotlib "
                 "(scripts/install-deps.sh)\n";
    return 1;
  }
  std::cout << "wrote " << dir << "/{table1,fig7,fig8,table2}.{csv,png} and " << dir << "/paper.md in " << std::fixed
            << std::setprecision(1) << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()
            << " s\n";
  return any_stopped(run) ? 1 : 0;
}

}  // namespace dw::bench
