// paper_report.cpp: the fits, the verdicts on the paper's claims, the CSV files and paper.md.
#include "bench/paper_report.h"

#include <gtest/gtest.h>

#include <sstream>

namespace dw::bench {
namespace {

TEST(FitLine, ThroughALineExactly) {
  const std::vector<double> x{100, 400, 700, 1000}, y{0.5, 1.1, 1.7, 2.3};
  const LinearFit f = fit_line(x, y);
  EXPECT_NEAR(f.slope, 0.002, 1e-12);
  EXPECT_NEAR(f.intercept, 0.3, 1e-12);
  EXPECT_NEAR(f.r_squared, 1, 1e-12);
  EXPECT_NEAR(f.at(250), 0.8, 1e-12);
}

TEST(FitLine, LeastSquaresAndRSquaredOfScatteredPoints) {
  // By hand: slope 9.5 / 5 = 1.9, intercept 4.75 - 1.9 * 2.5 = 0, SS_res 0.70, SS_tot 18.75.
  const LinearFit f = fit_line(std::vector<double>{1, 2, 3, 4}, std::vector<double>{2, 4, 5, 8});
  EXPECT_NEAR(f.slope, 1.9, 1e-12);
  EXPECT_NEAR(f.intercept, 0, 1e-12);
  EXPECT_NEAR(f.r_squared, 1 - 0.70 / 18.75, 1e-12);
}

TEST(FitLine, ConstantValuesFitExactly) {
  const LinearFit f = fit_line(std::vector<double>{1, 2, 3}, std::vector<double>{4, 4, 4});
  EXPECT_EQ(f.slope, 0);
  EXPECT_EQ(f.r_squared, 1);
}

// A run whose measurements are the paper's own numbers: Table I as published, Fig. 8 linear with
// the published mean overheads, Table II with the published overheads over a 1 s baseline.
PaperRun paper_as_measured() {
  PaperRun run;
  run.args.size = 10;
  run.args.steps = 100;
  run.groups_per_step = 62'418;
  for (const paper::Table1Row& p : paper::kTable1) {
    PaperTable1Row r;
    r.tuple = std::string(p.tuple);
    r.live.matches = p.matches;
    r.live.seconds = p.seconds;
    r.one_per_group = double(p.matches) * 1.5;
    run.table1.push_back(r);
  }
  for (uint32_t k = 1; k <= 10; ++k) {
    Fig8Row r;
    r.planes = k;
    r.modules = 100 * k;
    r.runs[kNoWatch].seconds = 0.01 * k;
    r.runs[kCentralized].seconds = 0.01 * k * (1 + paper::kFig8CentralizedOverhead / 100);
    r.runs[kDistributed].seconds = 0.01 * k * (1 + paper::kFig8DistributedOverhead / 100);
    run.fig8.push_back(r);
  }
  for (size_t f = 0; f < paper::kFrequencies.size(); ++f) {
    run.table2_baseline[f].seconds = 1;
    for (int size = 1; size <= paper::kTable2Sizes; ++size)
      run.table2[size_t(size - 1)][f].seconds = 1 + paper::kTable2[size - 1][f] / 100;
  }
  return run;
}

TEST(Verdicts, ThePapersOwnNumbersPassEveryCriterion) {
  const PaperRun run = paper_as_measured();
  EXPECT_NEAR(fig8_mean_overhead(run, kCentralized), 118, 1e-9);
  EXPECT_NEAR(fig8_mean_overhead(run, kDistributed), 105, 1e-9);
  EXPECT_NEAR(table2_overhead(run, 5, 2), 1432.5, 1e-9);
  const std::vector<Verdict> judged = verdicts(run);
  ASSERT_EQ(judged.size(), 11u);
  for (const Verdict& v : judged) EXPECT_TRUE(v.holds) << v.claim << ": " << v.measured;
}

TEST(Verdicts, EachClaimFailsWhenItsFigureDoes) {
  auto verdict = [](const PaperRun& run, std::string_view start) {
    for (const Verdict& v : verdicts(run))
      if (v.claim.rfind(start, 0) == 0) return v;
    ADD_FAILURE() << "no verdict starting " << start;
    return Verdict{};
  };
  PaperRun run = paper_as_measured();
  run.table1[4].live.seconds = 180;  // [8:4:2:1] as slow as [1:2:4:8]
  EXPECT_FALSE(verdict(run, "[1:2:4:8] takes almost 6 times").holds);
  EXPECT_EQ(verdict(run, "[1:2:4:8] takes almost 6 times").measured, "183.000 s and 180.000 s (1.0×)");

  run = paper_as_measured();
  for (Fig8Row& r : run.fig8) r.runs[kDistributed].seconds = r.runs[kCentralized].seconds * 1.1;
  EXPECT_FALSE(verdict(run, "The distributed version costs less").holds);
  EXPECT_TRUE(verdict(run, "All three series scale linearly").holds);

  run = paper_as_measured();
  run.fig8[9].runs[kNoWatch].seconds = 0.5;  // one size far off the line
  EXPECT_FALSE(verdict(run, "All three series scale linearly").holds);

  run = paper_as_measured();
  run.table2[4][2].seconds = 100;  // size 5, high: a 100x slowdown
  EXPECT_FALSE(verdict(run, "The most extreme example").holds);
  EXPECT_EQ(verdict(run, "The most extreme example").measured, "100.0× (9900%)");

  run = paper_as_measured();
  run.table2[3][2].seconds = 20;  // high: size 4 above size 5
  EXPECT_FALSE(verdict(run, "Medium and high frequencies").holds);
}

TEST(PaperMarkdown, NamesTheReadingThatFitsThePapersCounts) {
  PaperRun run = paper_as_measured();
  std::string md = paper_markdown(run, verdicts(run));
  // Its chain bindings are the paper's matches here, so that reading fits, within 0.0%.
  EXPECT_NE(md.find("**The paper's numbers fit \"chain bindings\"**: every row within 0.0% of the paper."),
            std::string::npos)
      << md;
  for (PaperTable1Row& r : run.table1) {
    r.live.matches = r.live.matches * 2;
    r.one_per_group = double(paper::table1(r.tuple)->matches) * 1.01;
  }
  md = paper_markdown(run, verdicts(run));
  EXPECT_NE(md.find("**The paper's numbers fit \"one per group\"**: every row within 1.0% of the paper."),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("dwatch's chain bindings are 2.00–2.00× the paper's matches in every row"), std::string::npos);
  for (PaperTable1Row& r : run.table1) r.one_per_group *= 1.5;
  md = paper_markdown(run, verdicts(run));
  EXPECT_NE(md.find("No reading fits every row within 2%"), std::string::npos);
}

TEST(PaperMarkdown, SetsEveryTableTwoCellBesideThePapers) {
  const PaperRun run = paper_as_measured();
  const std::string md = paper_markdown(run, verdicts(run));
  EXPECT_NE(md.find("| 5 | 23.0% [23%] | 83.4% [83.4%] | 1432.5% [1432.5%] |"), std::string::npos) << md;
  EXPECT_NE(md.find("| [1:1:1:1] | 6,233,141 | 6,233,141 | 1.00× | 715 | 715.000 | 1× |"), std::string::npos) << md;
}

TEST(PaperCsv, ColumnsThePlotScriptReads) {
  const PaperRun run = paper_as_measured();
  std::ostringstream t1, t2, f8;
  write_table1_csv(run, t1);
  write_table2_csv(run, t2);
  write_fig8_csv(run, f8);
  EXPECT_EQ(t1.str().substr(0, t1.str().find('\n')),
            "modules,steps,tuple,paper_matches,paper_seconds,matches,best_seconds,median_seconds,created,messages,"
            "peak_mib,chain_sets,groups_matched,one_per_group,stopped");
  EXPECT_NE(t1.str().find("\n1000,100,2:1:1:1,3119538,358,3119538,358,"), std::string::npos) << t1.str();
  // Size 5, high: the overhead and the paper's, side by side.
  EXPECT_NE(t2.str().find("\n1000,100,5,high,2,random_vars,1,15.325,0,1432.5,1432.5,"), std::string::npos) << t2.str();
  // The fit of each series, at each size, and its R².
  EXPECT_NE(f8.str().find("\n100,10,1000,distributed,0.205,0,0,0.205,1,105,0\n"), std::string::npos) << f8.str();
  EXPECT_NE(f8.str().find("\n100,10,1000,no watchpoint,0.1,0,0,0.1,1,,0\n"), std::string::npos) << f8.str();
}

}  // namespace
}  // namespace dw::bench
