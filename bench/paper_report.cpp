#include "bench/paper_report.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace dw::bench {
namespace {

std::string fixed(double v, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

// 1234567 -> "1,234,567"
std::string grouped(double v) {
  std::string digits = fixed(std::round(v), 0), out;
  const size_t lead = digits[0] == '-' ? 1 : 0;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > lead && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

std::string ratio(double ours, double theirs) { return theirs > 0 ? fixed(ours / theirs, 2) + "×" : "—"; }

const PaperTable1Row* table1_row(const PaperRun& run, std::string_view tuple) {
  for (const PaperTable1Row& r : run.table1)
    if (r.tuple == tuple) return &r;
  return nullptr;
}

uint64_t modules(const PaperRun& run) { return uint64_t(run.args.size) * run.args.size * run.args.size; }

double mib(const RuntimeRow& r) { return static_cast<double>(r.peak_kib) / 1024.0; }

// The ways Table I's matches can be counted, and each one's count for a row.
struct Reading {
  const char* name;
  const char* what;
  double (*count)(const PaperTable1Row&);
};
constexpr Reading kReadings[] = {
    {"chain bindings", "dwatch's matches: every assignment of slots to an ordered chain (the paper's Alg. 2)",
     [](const PaperTable1Row& r) { return double(r.live.matches); }},
    {"chain sets", "distinct module sets among those matches, each once per step",
     [](const PaperTable1Row& r) { return double(r.chain_sets); }},
    {"connected groups", "connected 4-module groups with some matching assignment, each once per step (shape any)",
     [](const PaperTable1Row& r) { return double(r.groups_matched); }},
    {"one per group", "each connected group counted once with one fixed assignment: groups × steps × Π 1/max_i",
     [](const PaperTable1Row& r) { return r.one_per_group; }},
};

// The largest |count / paper - 1| of a reading over the rows the paper publishes.
double worst_deviation(const PaperRun& run, const Reading& reading) {
  double worst = 0;
  for (const PaperTable1Row& r : run.table1)
    if (const auto p = paper::table1(r.tuple))
      worst = std::max(worst, std::abs(reading.count(r) / double(p->matches) - 1));
  return worst;
}

}  // namespace

LinearFit fit_line(std::span<const double> x, std::span<const double> y) {
  LinearFit f;
  const size_t n = std::min(x.size(), y.size());
  if (n == 0) return f;
  double mx = 0, my = 0;
  for (size_t i = 0; i < n; ++i) mx += x[i], my += y[i];
  mx /= double(n), my /= double(n);
  double sxx = 0, sxy = 0, syy = 0;
  for (size_t i = 0; i < n; ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
    syy += (y[i] - my) * (y[i] - my);
  }
  f.slope = sxx > 0 ? sxy / sxx : 0;
  f.intercept = my - f.slope * mx;
  double residual = 0;
  for (size_t i = 0; i < n; ++i) residual += (y[i] - f.at(x[i])) * (y[i] - f.at(x[i]));
  f.r_squared = syy > 0 ? 1 - residual / syy : (residual == 0 ? 1 : 0);
  return f;
}

const char* fig8_series_name(int series) {
  static constexpr const char* kNames[kFig8Series] = {"no watchpoint", "centralized", "distributed"};
  return kNames[series];
}

LinearFit fig8_fit(const PaperRun& run, int series) {
  std::vector<double> x, y;
  for (const Fig8Row& r : run.fig8) {
    x.push_back(r.modules);
    y.push_back(r.runs[size_t(series)].seconds);
  }
  return fit_line(x, y);
}

double fig8_mean_overhead(const PaperRun& run, int series) {
  double sum = 0;
  for (const Fig8Row& r : run.fig8) sum += 100 * (r.runs[size_t(series)].seconds / r.runs[kNoWatch].seconds - 1);
  return run.fig8.empty() ? 0 : sum / double(run.fig8.size());
}

double table2_overhead(const PaperRun& run, int size, size_t frequency) {
  return 100 * (run.table2[size_t(size - 1)][frequency].seconds / run.table2_baseline[frequency].seconds - 1);
}

std::vector<Verdict> verdicts(const PaperRun& run) {
  std::vector<Verdict> out;
  auto add = [&](std::string claim, std::string published, std::string measured, std::string criterion, bool holds) {
    out.push_back({std::move(claim), std::move(published), std::move(measured), std::move(criterion), holds});
  };
  const PaperTable1Row* all = table1_row(run, "1:1:1:1");
  const PaperTable1Row* half = table1_row(run, "2:1:1:1");
  const PaperTable1Row* sixteenth = table1_row(run, "2:2:2:2");
  const PaperTable1Row* late = table1_row(run, "1:2:4:8");
  const PaperTable1Row* early = table1_row(run, "8:4:2:1");
  const auto p_all = *paper::table1("1:1:1:1"), p_half = *paper::table1("2:1:1:1"),
             p_sixteenth = *paper::table1("2:2:2:2"), p_late = *paper::table1("1:2:4:8"),
             p_early = *paper::table1("8:4:2:1");
  if (all && half && sixteenth) {
    const double r2 = double(all->live.matches) / double(half->live.matches);
    const double r16 = double(all->live.matches) / double(sixteenth->live.matches);
    add("[2:1:1:1] halves the matches of [1:1:1:1]; [2:2:2:2] divides them by 16 (§V-A)",
        "÷" + fixed(double(p_all.matches) / double(p_half.matches), 2) + " and ÷" +
            fixed(double(p_all.matches) / double(p_sixteenth.matches), 1),
        "÷" + fixed(r2, 2) + " and ÷" + fixed(r16, 1), "each within 10% of ÷2 and ÷16",
        std::abs(r2 / 2 - 1) <= 0.1 && std::abs(r16 / 16 - 1) <= 0.1);
  }
  if (late && early) {
    const double m = double(late->live.matches) / double(early->live.matches);
    add("[1:2:4:8] and [8:4:2:1] give almost the same number of matches (§V-A)",
        grouped(double(p_late.matches)) + " and " + grouped(double(p_early.matches)) + " (" +
            fixed(double(p_late.matches) / double(p_early.matches), 2) + "×)",
        grouped(double(late->live.matches)) + " and " + grouped(double(early->live.matches)) + " (" + fixed(m, 2) +
            "×)",
        "within 10% of each other", std::abs(m - 1) <= 0.1);
    const double t = late->live.seconds / early->live.seconds;
    add("[1:2:4:8] takes almost 6 times as long as [8:4:2:1] (§V-A)",
        fixed(p_late.seconds, 0) + " s and " + fixed(p_early.seconds, 0) + " s (" +
            fixed(p_late.seconds / p_early.seconds, 1) + "×)",
        fixed(late->live.seconds, 3) + " s and " + fixed(early->live.seconds, 3) + " s (" + fixed(t, 1) + "×)",
        "between 3× and 12× (within a factor of two of 6×)",
        t >= paper::kTrajectoryTimeRatio / 2 && t <= paper::kTrajectoryTimeRatio * 2);
  }
  if (run.table1.size() >= 3) {
    std::vector<double> x, y;
    for (const PaperTable1Row& r : run.table1) x.push_back(double(r.live.matches)), y.push_back(r.live.seconds);
    const LinearFit f = fit_line(x, y);
    std::vector<double> px, py;
    for (const paper::Table1Row& r : paper::kTable1) px.push_back(double(r.matches)), py.push_back(r.seconds);
    add("Time grows about linearly with the number of matches (Table I, §V-A)",
        "R² " + fixed(fit_line(px, py).r_squared, 3) + " over its five rows",
        "R² " + fixed(f.r_squared, 3) + " over " + std::to_string(x.size()) + " rows", "R² ≥ 0.8", f.r_squared >= 0.8);
  }
  if (run.fig8.size() >= 3) {
    std::string measured;
    bool linear = true;
    for (int s = 0; s < kFig8Series; ++s) {
      const double r2 = fig8_fit(run, s).r_squared;
      measured += std::string(s ? ", " : "") + fig8_series_name(s) + " R² " + fixed(r2, 3);
      linear = linear && r2 >= 0.95;
    }
    add("All three series scale linearly with the ensemble's size (Fig. 8, §V-B)", "linear (no fit published)",
        measured, "R² ≥ 0.95 for each linear fit", linear);
    const double c = fig8_mean_overhead(run, kCentralized), d = fig8_mean_overhead(run, kDistributed);
    add("Mean overhead over the medium-intensity workload: 118% centralized, 105% distributed (Fig. 8, §V-B)",
        "118% and 105%", fixed(c, 0) + "% and " + fixed(d, 0) + "%", "each within a factor of two of the paper's",
        c >= 59 && c <= 236 && d >= 52.5 && d <= 210);
    add("The distributed version costs less than the centralized one (§V-B, on a dual-core machine)", "105% < 118%",
        fixed(d, 0) + "% vs " + fixed(c, 0) + "% on " + std::to_string(run.args.threads) +
            (run.args.threads == 1 ? " thread" : " threads"),
        "distributed overhead < centralized", d < c);
    add("Reasonable watchpoints introduce overhead of 100% or less (§VI)", "≤ 100% (Fig. 8: 105–118%)",
        "Fig. 8: " + fixed(c, 0) + "% and " + fixed(d, 0) + "%",
        "both Fig. 8 means ≤ 120%, the paper's own example of reasonable",
        c <= paper::kReasonableOverhead * 1.2 && d <= paper::kReasonableOverhead * 1.2);
  }
  const size_t high = 2, low = 0, medium = 1;
  const double worst = 1 + table2_overhead(run, paper::kTable2Sizes, high) / 100;
  const double paper_worst = paper::kTable2[paper::kTable2Sizes - 1][high];
  add("The most extreme example is a slowdown of about fourteen times (Table II, size 5, high; §VI)",
      fixed(1 + paper_worst / 100, 1) + "× (" + fixed(paper_worst, 1) + "%)",
      fixed(worst, 1) + "× (" + fixed(100 * (worst - 1), 0) + "%)",
      "between 7× and 28× (within a factor of two of 14×)",
      worst >= paper::kWorstSlowdown / 2 && worst <= paper::kWorstSlowdown * 2);
  bool growing = true;
  std::string high_row;
  for (int size = 1; size <= paper::kTable2Sizes; ++size) {
    high_row += (size > 1 ? ", " : "") + fixed(table2_overhead(run, size, high), 0) + "%";
    if (size > 1) growing = growing && table2_overhead(run, size, high) > table2_overhead(run, size - 1, high);
  }
  growing = growing && table2_overhead(run, 5, medium) > table2_overhead(run, 1, medium);
  add("Medium and high frequencies cost more as the expression grows (Table II, §V-C)",
      "high: 3.6, 54.4, 104.7, 369.8, 1432.5%", "high: " + high_row,
      "high grows with every size, medium's size 5 above its size 1", growing);
  double lo = 1e300, hi = -1e300;
  for (int size = 1; size <= paper::kTable2Sizes; ++size) {
    lo = std::min(lo, table2_overhead(run, size, low));
    hi = std::max(hi, table2_overhead(run, size, low));
  }
  add("At low frequency the overhead varies only a little with size (Table II, §V-C)", "7.6% to 42.6% (35 points)",
      fixed(lo, 0) + "% to " + fixed(hi, 0) + "% (" + fixed(hi - lo, 0) + " points)", "a spread of ≤ 50 points",
      hi - lo <= 50);
  return out;
}

void write_table1_csv(const PaperRun& run, std::ostream& out) {
  out << std::setprecision(10);  // seconds of a few milliseconds keep their digits
  const std::string ensemble = std::to_string(modules(run)) + "," + std::to_string(run.args.steps) + ",";
  out << "modules,steps,tuple,paper_matches,paper_seconds,matches,best_seconds,median_seconds,created,messages,peak_"
         "mib,"
         "chain_sets,groups_matched,one_per_group,stopped\n";
  for (const PaperTable1Row& r : run.table1) {
    const auto p = paper::table1(r.tuple);
    out << ensemble << r.tuple << "," << (p ? std::to_string(p->matches) : "") << "," << (p ? fixed(p->seconds, 0) : "")
        << "," << r.live.matches << "," << r.live.seconds << "," << r.live.median_seconds << "," << r.live.created
        << "," << r.live.messages << "," << fixed(mib(r.live), 1) << "," << r.chain_sets << "," << r.groups_matched
        << "," << fixed(r.one_per_group, 0) << "," << r.live.stopped << "\n";
  }
}

void write_fig7_csv(const PaperRun& run, std::ostream& out) {
  const std::string ensemble = std::to_string(modules(run)) + "," + std::to_string(run.args.steps) + ",";
  out << "modules,steps,tuple,algorithm,filled,created\n";
  for (const PaperTable1Row& r : run.table1)
    for (const auto& [name, row] : {std::pair{"distributed", &r.distributed}, std::pair{"centralized", &r.centralized}})
      for (int filled = 1; filled <= 4; ++filled)
        out << ensemble << r.tuple << "," << name << "," << filled << "," << row->by_filled[filled] << "\n";
}

void write_fig8_csv(const PaperRun& run, std::ostream& out) {
  out << std::setprecision(10);  // seconds of a few milliseconds keep their digits
  out << "steps,planes,modules,series,best_seconds,median_seconds,matches,fit_seconds,r_squared,"
         "paper_overhead_percent,stopped\n";
  for (int s = 0; s < kFig8Series; ++s) {
    const LinearFit fit = fig8_fit(run, s);
    const std::string published = s == kCentralized   ? fixed(paper::kFig8CentralizedOverhead, 0)
                                  : s == kDistributed ? fixed(paper::kFig8DistributedOverhead, 0)
                                                      : "";
    for (const Fig8Row& r : run.fig8) {
      const RuntimeRow& x = r.runs[size_t(s)];
      out << run.args.steps << "," << r.planes << "," << r.modules << "," << fig8_series_name(s) << "," << x.seconds
          << "," << x.median_seconds << "," << x.matches << "," << fit.at(r.modules) << "," << fit.r_squared << ","
          << published << "," << x.stopped << "\n";
    }
  }
}

void write_table2_csv(const PaperRun& run, std::ostream& out) {
  out << std::setprecision(10);  // seconds of a few milliseconds keep their digits
  const std::string ensemble = std::to_string(modules(run)) + "," + std::to_string(run.args.steps) + ",";
  out << "modules,steps,size,frequency,max,workload,baseline_seconds,best_seconds,median_seconds,overhead_percent,"
         "paper_overhead_percent,matches,created,stopped\n";
  for (int size = 1; size <= paper::kTable2Sizes; ++size)
    for (size_t f = 0; f < paper::kFrequencies.size(); ++f) {
      const RuntimeRow& x = run.table2[size_t(size - 1)][f];
      out << ensemble << size << "," << paper::kFrequencies[f].name << "," << paper::kFrequencies[f].max << ","
          << run.args.table2_workload << "," << run.table2_baseline[f].seconds << "," << x.seconds << ","
          << x.median_seconds << "," << table2_overhead(run, size, f) << "," << paper::kTable2[size - 1][f] << ","
          << x.matches << "," << x.created << "," << x.stopped << "\n";
    }
}

std::string paper_command(const PaperRun& run) {
  const BenchArgs& a = run.args;
  std::string c = "dwatch bench paper --out " + out_dir(a);
  if (a.quick) c += " --quick";
  c += " --repeat " + std::to_string(a.repeat) + " --threads " + std::to_string(a.threads);
  if (a.size != 10) c += " --size " + std::to_string(a.size);
  if (a.steps != 100) c += " --steps " + std::to_string(a.steps);
  if (a.seed != 1) c += " --seed " + std::to_string(a.seed);
  if (a.table2_workload != "random_vars") c += " --table2-workload " + a.table2_workload;
  const shell::DetectorFlags& d = a.detector;
  if (d.no_early_termination) c += " --no-early-termination";
  if (d.no_neighbor_culling) c += " --no-neighbor-culling";
  if (d.no_temporal_spans) c += " --no-temporal-spans";
  if (d.max_live != shell::DetectorFlags{}.max_live) c += " --max-live " + std::to_string(d.max_live);
  return c;
}

std::string out_dir(const BenchArgs& args) { return args.out_dir.empty() ? "paper" : args.out_dir; }

std::string plot_command(const std::string& dir, const std::string& script) {
  // Debian's matplotlib is only importable by Debian's interpreter (docs/design.md §9).
  return "/usr/bin/python3 '" + script + "' '" + dir + "'";
}

namespace {

// The title, how the run was made, on what, and the verdicts.
void markdown_intro(std::ostream& md, const PaperRun& run, const std::vector<Verdict>& judged) {
  const BenchArgs& a = run.args;
  const std::string cube = std::to_string(a.size) + "³";
  md << "# The paper's evaluation, regenerated\n\n"
     << "Every table and figure of §V of *Distributed Watchpoints* (De Rosa et al.), measured by dwatch " << run.version
     << " on " << run.date << ", beside the numbers the paper publishes. Made by:\n\n"
     << "```\n"
     << paper_command(run) << "\n"
     << plot_command(out_dir(a), "scripts/plot_paper.py") << "   # the plots, from the CSV files\n```\n\n"
     << "- **Machine:** " << run.cpu << ", " << run.cores << " cores, load average " << fixed(run.load_average, 2)
     << " at the start. The paper: DPRSim on dual-core Linux machines (2011).\n"
     << "- **Ensemble:** a " << cube << " cubic lattice (" << grouped(double(modules(run))) << " modules), " << a.steps
     << " steps, seed " << a.seed << ", " << a.threads << (a.threads == 1 ? " thread" : " threads")
     << " stepping modules; physics and rendering off, as in the paper.\n"
     << "- **Times** are of the steps alone. Every row is timed in " << a.repeat
     << (a.repeat == 1 ? " pass" : " passes") << " over all the rows, each pass the best of runs adding up to "
     << fixed(paper_min_seconds(a), 2)
     << " s, and keeps its fastest pass (the median pass is in the CSV files): a burst of load from elsewhere "
        "slows one pass of many rows rather than every run of one.\n"
     << "- **Watchpoint:** Fig. 6, `" << kFig6 << "`, host program `random_vars` (x_i uniform in 0..max_i − 1).\n\n";

  md << "## Verdicts\n\n| claim | paper | dwatch | holds when | verdict |\n|---|---|---|---|---|\n";
  for (const Verdict& v : judged)
    md << "| " << v.claim << " | " << v.paper << " | " << v.measured << " | " << v.criterion << " | "
       << (v.holds ? "**holds**" : "**does not hold**") << " |\n";
}

// Table I beside the paper's, and which reading of its "matches" the paper's numbers fit.
void markdown_table1(std::ostream& md, const PaperRun& run) {
  const BenchArgs& a = run.args;
  const std::string cube = std::to_string(a.size) + "³";
  md << "\n## Table I: matches and time per host-program tuple (distributed, " << a.size * a.size * a.size
     << " modules)\n\n![Table I](table1.png)\n\n"
     << "| tuple | paper matches | dwatch matches | ratio | paper s | dwatch s | paper ÷ dwatch | PatternMatchers | "
        "messages | peak MiB |\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const PaperTable1Row& r : run.table1) {
    const auto p = paper::table1(r.tuple);
    md << "| [" << r.tuple << "] | " << (p ? grouped(double(p->matches)) : "—") << " | "
       << grouped(double(r.live.matches)) << " | " << ratio(double(r.live.matches), p ? double(p->matches) : 0) << " | "
       << (p ? fixed(p->seconds, 0) : "—") << " | " << fixed(r.live.seconds, 3) << " | "
       << (p ? grouped(p->seconds / r.live.seconds) + "×" : "—") << " | " << grouped(double(r.live.created)) << " | "
       << grouped(double(r.live.messages)) << " | " << fixed(mib(r.live), 1) << " |\n";
  }
  md << "\nThe live run (the host program stepping, the watchpoint hosted by the runtime) and the watch engine "
        "over the recorded trace of the same ensemble found the same matches in every row.\n";

  md << "\n### Which count is the paper's\n\n"
     << "The " << cube << " lattice has " << grouped(double(run.groups_per_step))
     << " connected groups of four modules per step. Each reading of Table I's \"matches\", as a ratio to the "
        "paper's:\n\n| reading | what it counts |";
  for (const PaperTable1Row& r : run.table1) md << " [" << r.tuple << "] |";
  md << " worst |\n|---|---|";
  for (size_t i = 0; i <= run.table1.size(); ++i) md << "---|";
  md << "\n";
  const Reading* best = nullptr;
  for (const Reading& reading : kReadings) {
    md << "| " << reading.name << " | " << reading.what << " |";
    for (const PaperTable1Row& r : run.table1) {
      const auto p = paper::table1(r.tuple);
      md << " " << grouped(reading.count(r)) << " (" << ratio(reading.count(r), p ? double(p->matches) : 0) << ") |";
    }
    const double worst = worst_deviation(run, reading);
    md << " " << fixed(100 * worst, 1) << "% |\n";
    if (!best || worst < worst_deviation(run, *best)) best = &reading;
  }
  if (best && worst_deviation(run, *best) <= 0.02) {
    md << "\n**The paper's numbers fit \"" << best->name << "\"**: every row within "
       << fixed(100 * worst_deviation(run, *best), 1) << "% of the paper.";
  } else if (best) {
    md << "\nNo reading fits every row within 2%; the closest is \"" << best->name << "\" ("
       << fixed(100 * worst_deviation(run, *best), 1) << "%).";
  }
  double low = 1e300, high = 0;
  for (const PaperTable1Row& r : run.table1)
    if (const auto p = paper::table1(r.tuple)) {
      low = std::min(low, double(r.live.matches) / double(p->matches));
      high = std::max(high, double(r.live.matches) / double(p->matches));
    }
  if (high > 0)
    md << " dwatch's chain bindings are " << fixed(low, 2) << "–" << fixed(high, 2)
       << "× the paper's matches in every row: they fall with Π 1/max_i as the paper's do, so the paper counted "
          "a fixed fraction of them. Distinct module sets do not fall that way: a set is kept when *some* "
          "assignment of its modules matches, so for [2:1:1:1] about 15/16 of the groups (one of four modules "
          "with x1 = 0) rather than half. Counting each connected group once with one assignment of slots fixed "
          "before the values are known gives the paper's numbers in every row; an enumeration that reaches each "
          "set of modules once, in one order (as ESU does, docs/design.md §4a), counts that way. Alg. 2's chains "
          "cannot "
          "form the star-shaped groups (one module beside the three others) at all. dwatch keeps the paper's stated "
          "semantics for its "
          "matches (docs/design.md §4); `shape = \"any\"` finds every connected group.\n";
}

// Fig. 7's PatternMatchers by slots filled, and Fig. 8's times against ensemble size with their fits.
void markdown_figures(std::ostream& md, const PaperRun& run) {
  const BenchArgs& a = run.args;
  md << "\n## Fig. 7: PatternMatchers created by slots filled (" << grouped(double(modules(run))) << " modules, "
     << a.steps << " steps)\n\n![Fig. 7](fig7.png)\n\n"
     << "The paper prints Fig. 7 as a plot without values, so there is nothing to set these beside; its text "
        "says [1:1:1:1] explodes, [2:2:2:2] cuts it by halves at each slot, and [1:2:4:8] culls late while "
        "[8:4:2:1] culls early.\n\n| tuple | reading | 1 | 2 | 3 | 4 |\n|---|---|---|---|---|---|\n";
  for (const PaperTable1Row& r : run.table1)
    for (const auto& [name, row] :
         {std::pair{"distributed", &r.distributed}, std::pair{"centralized", &r.centralized}}) {
      md << "| [" << r.tuple << "] | " << name << " |";
      for (int filled = 1; filled <= 4; ++filled) md << " " << grouped(double(row->by_filled[filled])) << " |";
      md << "\n";
    }

  md << "\n## Fig. 8: time against ensemble size (" << a.size << " × " << a.size
     << " stacked planes, aggregation_routing + random_vars [2:2:2:2])\n\n![Fig. 8](fig8.png)\n\n"
     << "| modules | no watchpoint s | centralized s | overhead | distributed s | overhead |\n"
        "|---|---|---|---|---|---|\n";
  for (const Fig8Row& r : run.fig8) {
    const double none = r.runs[kNoWatch].seconds;
    md << "| " << r.modules << " | " << fixed(none, 4) << " | " << fixed(r.runs[kCentralized].seconds, 4) << " | "
       << fixed(100 * (r.runs[kCentralized].seconds / none - 1), 0) << "% | " << fixed(r.runs[kDistributed].seconds, 4)
       << " | " << fixed(100 * (r.runs[kDistributed].seconds / none - 1), 0) << "% |\n";
  }
  md << "\n| series | seconds per 1,000 modules (slope) | R² | mean overhead | the paper |\n|---|---|---|---|---|\n";
  for (int s = 0; s < kFig8Series; ++s) {
    const LinearFit f = fig8_fit(run, s);
    md << "| " << fig8_series_name(s) << " | " << fixed(1000 * f.slope, 4) << " | " << fixed(f.r_squared, 3) << " | "
       << (s == kNoWatch ? "—" : fixed(fig8_mean_overhead(run, s), 0) + "%") << " | "
       << (s == kNoWatch       ? "linear"
           : s == kCentralized ? "linear, 118%"
                               : "linear, 105%")
       << " |\n";
  }
}

// Table II: the overhead of each expression size at each frequency, beside the paper's.
void markdown_table2(std::ostream& md, const PaperRun& run) {
  const BenchArgs& a = run.args;
  md << "\n## Table II: overhead against expression size (centralized, " << a.size * a.size * a.size
     << " modules)\n\n![Table II](table2.png)\n\n"
     << "Expressions `modules(s1..sk); (s1.x1 = 0) and ... and (sk.xk = 0)`. The paper does not say what its "
        "baseline ran; here it is **"
     << (a.table2_workload == "random_vars" ? "random_vars alone" : "random_vars with aggregation_routing")
     << "** (five variables at the column's frequency; `--table2-workload` changes it). Each cell: dwatch "
        "[paper], in percent.\n\n| size |";
  for (const paper::Frequency& f : paper::kFrequencies) md << " " << f.name << " (max " << f.max << ") |";
  md << "\n|---|---|---|---|\n";
  for (int size = 1; size <= paper::kTable2Sizes; ++size) {
    md << "| " << size << " |";
    for (size_t f = 0; f < paper::kFrequencies.size(); ++f)
      md << " " << fixed(table2_overhead(run, size, f), 1) << "% [" << paper::kTable2[size - 1][f] << "%] |";
    md << "\n";
  }
  md << "\n| frequency | baseline s |";
  for (int size = 1; size <= paper::kTable2Sizes; ++size) md << " size " << size << " s |";
  md << "\n|---|---|---|---|---|---|---|\n";
  for (size_t f = 0; f < paper::kFrequencies.size(); ++f) {
    md << "| " << paper::kFrequencies[f].name << " | " << fixed(run.table2_baseline[f].seconds, 4) << " |";
    for (int size = 1; size <= paper::kTable2Sizes; ++size)
      md << " " << fixed(run.table2[size_t(size - 1)][f].seconds, 4) << " |";
    md << "\n";
  }
}

// What the overheads mean beside DPRSim's own speed.
void markdown_overheads(std::ostream& md, const PaperRun& run) {
  const BenchArgs& a = run.args;
  const PaperTable1Row* all = table1_row(run, "1:1:1:1");
  const paper::Table1Row p_mid = *paper::table1("2:2:2:2"), p_all = *paper::table1("1:1:1:1");
  const double paper_module_step = p_mid.seconds / double(paper::kModules) / double(paper::kSteps);
  md << "\n## Reading the overheads\n\n"
     << "An overhead is the watchpoint's cost divided by the simulator's own. DPRSim took "
     << fixed(1e3 * paper_module_step, 2)
     << " ms per module-step for [2:2:2:2] with the watchpoint (Table I: " << fixed(p_mid.seconds, 0) << " s for "
     << grouped(paper::kModules) << " modules × " << paper::kSteps << " steps)";
  if (const PaperTable1Row* mid = table1_row(run, "2:2:2:2")) {
    const double module_step = mid->live.seconds / double(modules(run)) / double(a.steps);
    md << "; dwatch takes " << fixed(1e6 * module_step, 2) << " µs, " << grouped(paper_module_step / module_step)
       << "× less";
  }
  md << ". The baseline workloads are cheaper still, so the same watchpoint is a larger fraction of a run: the "
        "percentages say how the watch's cost compares with dwatch's stepping, not that it costs more than the "
        "paper's.";
  if (all)
    md << " The worst case, [1:1:1:1], took " << fixed(all->live.seconds, 3) << " s against the paper's "
       << fixed(p_all.seconds, 0) << " s.";
  md << "\n";
}

}  // namespace

std::string paper_markdown(const PaperRun& run, const std::vector<Verdict>& judged) {
  std::ostringstream md;
  markdown_intro(md, run, judged);
  markdown_table1(md, run);
  markdown_figures(md, run);
  markdown_table2(md, run);
  markdown_overheads(md, run);
  return md.str();
}

}  // namespace dw::bench
