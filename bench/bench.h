// `dwatch bench NAME`: reproductions of the paper's measurements.
//   engine    Table I on the watch engine alone, over a synthetic trace (bench_engine.cpp)
//   expressions  docs/design.md §4b's arithmetic and aggregates beside plain Fig. 6 (bench_expressions.cpp)
//   shapes    every group shape and state mode (docs/design.md §4a) on the engine: time, messages per match
//             (bench_shapes.cpp)
//   table1    Table I through the runtime: the host program running, the watchpoint live
//   overhead  the watchpoint's overhead over a medium-intensity workload (paper §V-B)
//   million   a 100^3 cube, [8:4:2:1], Fig. 6, distributed: time and memory at scale
//   mpi       the same over several processes (mpirun): time, bytes between ranks, memory per rank
//   physics   dwatch's physics step beside a plain persistent Bullet program doing the same scene
//             (unbonded boxes falling, an unbonded pile, bonded clusters, a latched lattice; the
//             ratio is the figure), then resting lattices and the watchpoint overhead over a
//             1,000-module physics run of leader election (bench_physics.cpp)
//   paper     the paper's whole §V: Table I, Fig. 7, Fig. 8, Table II beside its published numbers,
//             as CSV, plots and paper.md (bench_paper.cpp, paper_report.cpp, scripts/plot_paper.py)
//   render    frames of the headless 3D view at 1280x720, 1,000 and 10,000 modules, and a video of 200
//             (bench_render.cpp)
//   session   the session's history: live cost, keyframes, seek, retroactive watchpoints (bench_session.cpp)
//   lua       the Lua ports of scenarios/lua/ beside their C++ twins: speed and memory (bench_lua.cpp)
//   view      the debugger window: frames/s, and how fast a click shows its step (app/view/bench_view.cpp,
//             handed to add_bench_command: bench_command.h)
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "scenarios/scenario.h"
#include "shell/detector_flags.h"
#include "sim/output_file.h"
#include "sim/trace.h"
#include "watch/watchpoint.h"

namespace dw::bench {

// The paper's Fig. 6 watchpoint, as the benchmarks use it (x_i = 0 has probability 1/max_i).
constexpr const char* kFig6 = "modules(a b c d); (a.x1 = 0) and (b.x2 = 0) and (c.x3 = 0) and (d.x4 = 0)";

// Modules(s1 ... sk); (s1.x1 = 0) and ... and (sk.xk = 0): the paper's Table II expressions
// (Fig. 6 is the one of size 4, with slots a b c d).
std::string conjunction_watch(int size);

struct BenchArgs {
  std::string name;
  std::vector<std::string> tuples{"1:1:1:1", "2:1:1:1", "2:2:2:2", "1:2:4:8", "8:4:2:1"};
  std::string algorithm = "both";
  uint32_t size = 10;
  int64_t steps = 100;
  uint64_t seed = 1;
  unsigned threads = 1;
  std::string out_dir;
  std::string write_trace;
  int repeat = 5;
  bool quick = false;                           // paper: at most 2 passes, 4 sizes for Fig. 8
  std::string table2_workload = "random_vars";  // paper: Table II's baseline
  std::string partition = "auto";               // mpi: run --partition
  shell::DetectorFlags detector;
};

// The CSV file `--out DIR` asks for (DIR/NAME.csv, the folder made if need be), with its header
// line written; nullptr when no --out was given. False, with the error on stderr, when it cannot
// be written. It is committed (sim::OutputFile) when the benchmark is done.
bool open_csv(const BenchArgs& args, const std::string& name, const std::string& header,
              std::unique_ptr<sim::OutputFile>& out);

// "8:4:2:1" -> {8, 4, 2, 1}; empty unless four positive integers.
std::vector<int64_t> parse_tuple(const std::string& text);

// The Table I ensemble for one tuple ("2:2:2:2"): an args.size^3 cube of random_vars for
// args.steps steps; nothing, with the error on stderr, when the tuple is not four positive integers.
std::optional<sim::Trace> table1_trace(const BenchArgs& args, const std::string& tuple_text);

// One detector over a trace's frames, the way `bench engine` and `bench shapes` time it.
struct EngineRow {
  uint64_t matches = 0, created = 0, messages = 0, lost = 0, peak_live = 0;
  double seconds = 0;  // the fastest of the repeats
  double median_seconds = 0;
  long peak_kib = 0;
  bool stopped = false;
  uint64_t by_filled[5] = {};  // PatternMatchers by slots filled, 1..4 (the paper's Fig. 7)
};
// Runs a fresh detector over every frame `repeat` times (and drains it), counting matches; the
// frames are built before timing. Timing noise on a shared machine only ever adds, so the
// fastest run is the figure; the median is kept beside it. Four-slot watchpoints.
EngineRow run_engine_row(const sim::Trace& trace, const watch::Watchpoint& w, watch::Algorithm a,
                         const watch::DetectorOptions& o, int repeat);

// One detector over a trace's frames once, every match handed to `on_match` too (untimed counts).
using MatchSink = std::function<void(int64_t step, std::span<const watch::ModuleId> ids)>;
EngineRow count_engine_row(const sim::Trace& trace, const watch::Watchpoint& w, watch::Algorithm a,
                           const watch::DetectorOptions& o, const MatchSink& on_match);

// Scenario text for the runtime benchmarks, which go through the scenario loader like any file.
std::string cubic_toml(uint32_t nx, uint32_t ny, uint32_t nz);
// A bench's scenario text loaded; a mistake in it is written to stderr (nullopt).
std::optional<scenarios::Scenario> load_bench_scenario(const std::string& text);
std::string random_vars_toml(std::span<const int64_t> maxima);
// A counting [[watch]] read the way the command's flags say (--no-*, --max-live, --shape, --states).
std::string watch_toml(const std::string& name, const std::string& text, watch::Algorithm a,
                       const shell::DetectorFlags& flags);
// The paper's "medium-intensity workload" (§V-B): data aggregation and landmark routing.
inline constexpr const char* kAggregationToml = "[[program]]\nname = \"aggregation_routing\"\nlandmarks = 3\n";

// A scenario run from scratch `repeat` times in a child process (its peak memory its own).
struct RuntimeRow {
  uint64_t matches = 0, created = 0, messages = 0;  // of the first watch, if any
  double seconds = 0, median_seconds = 0;           // the fastest run, and the median
  double world_seconds = 0;                         // of the fastest run: in World::advance
  long peak_kib = 0;
  bool failed = false, stopped = false;  // stopped: the watch reached its --max-live budget
};
// What a row times: the steps of a run, or setting it up (loading the scenario, building its
// world and first state) and tearing it down again.
enum class Timed { Steps, SetUp };
// At least `repeat` runs, and more (up to 100) until the timed parts add up to `min_seconds`, so
// that a row of a few milliseconds is the best of many. False, with the error on stderr, when the
// run failed.
bool run_runtime_row(const std::string& toml, const BenchArgs& args, int repeat, RuntimeRow& row,
                     Timed timed = Timed::Steps, double min_seconds = 0);

int bench_engine(const BenchArgs& args);
int bench_paper(const BenchArgs& args);
int bench_shapes(const BenchArgs& args, bool tuples_given);
int bench_expressions(const BenchArgs& args, bool tuples_given);
int bench_runtime(const BenchArgs& args);  // table1, overhead, million, physics
int bench_mpi(const BenchArgs& args);      // bench_mpi.cpp
// The million-module ensemble at edge `size` (bench million, bench mpi): random_vars [8:4:2:1] and
// Fig. 6, distributed, counting; the default --max-live grows with the modules past a million.
std::string million_toml(uint32_t size, shell::DetectorFlags flags);
int bench_render(const BenchArgs& args);
int bench_session(const BenchArgs& args);
int bench_lua(const BenchArgs& args);

}  // namespace dw::bench
