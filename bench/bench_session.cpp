// `dwatch bench session`: what the session's history costs and buys (docs/design.md §7). Each row runs in
// a child process (its peak memory its own):
//   - the Table I ensemble (10^3 cube, random_vars [2:2:2:2], Fig. 6 distributed), 2,000 steps:
//     the live run with the history on against off, keyframe sizes (estimated by the session and
//     measured on the heap), and seeks to random steps;
//   - a 1,000-module physics scenario (leader election on a 40x25 hex sheet, latched), the same;
//   - a Fig. 6 watchpoint added after 1,000 steps of the Table I ensemble, evaluated over them;
//   - `session --protocol`'s round trip: `hash` written, its answer read, over pipes to a child;
//   - `why` at depth 3 (docs/design.md §7b) on 10,000 modules run to step 1,000, beside the seek
//     to that step: random_vars beside aggregation_routing (a value changed lately, its module
//     hearing its neighbours every step) and leader election (one unchanged
//     since early on, whose origin is searched far back);
//   - 100,000 steps of the Table I ensemble ([8:4:2:1]): the history's memory.
#include <malloc.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <functional>
#include <iomanip>
#include <iostream>
#include <random>
#include <string_view>

#include "bench/bench.h"
#include "bench/bench_child.h"
#include "scenarios/scenario.h"
#include "shell/output_files.h"
#include "sim/session.h"
#include "sim/why.h"

namespace dw::bench {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }
// The process's CPU time in seconds: on a machine others load, what a step costs apart from waiting.
double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

struct HistoryRow {
  double live_off = 0, live_on = 0;  // best seconds
  int64_t keyframes = 0, interval = 0;
  uint64_t history_bytes = 0;
  uint64_t state_bytes_measured = 0;              // heap taken by one copy of the latest state
  uint64_t in_flight_bytes = 0, agent_bytes = 0;  // of which: PatternMatchers in flight, agents
  double seek_max_ms = 0, seek_median_ms = 0;
  bool failed = false;
};

struct RetroRow {
  double seconds = 0;
  uint64_t matches = 0, fresh_matches = 0;
  bool failed = false;
};

// The Table I ensemble for a tuple, with the Fig. 6 watch read as `watch` says, or none.
std::string table1_text(const std::string& tuple, const shell::DetectorFlags* watch) {
  return "seed = 1\n" + cubic_toml(10, 10, 10) + random_vars_toml(parse_tuple(tuple)) +
         (watch ? watch_toml("fig6", kFig6, watch::Algorithm::Distributed, *watch) : "");
}

const std::string kPhysicsElection =
    "seed = 1\n[lattice]\nkind = \"hex2d\"\nsize = [40, 25]\n[[program]]\nname = \"leader_election\"\n"
    "[[watch]]\nname = \"two_leaders\"\naction = \"count\"\n"
    "text = \"modules(a b c); (a.isLeader = 1) and (c.isLeader = 1)\"\n[physics]\nenabled = true\n";

struct WhyRow {
  double seek_ms = 0, why_ms = 0, why_median_ms = 0;  // best of the repeats (and the median)
  double why_cpu_ms = 0;                              // the process's CPU time, best of the repeats
  int64_t origin = 0, interval = 0;
  uint32_t module = 0;
  uint64_t events = 0, messages = 0;
  bool failed = false;
};

// `why module VAR step --depth 3` after a run to `step`, the cursor at step 0 before each timing,
// beside `seek step` from there; the module is the first whose VAR changed within 4 steps of
// `step` (or module 0 when `lately` is false: its origin may lie far back).
WhyRow why_row(const std::string& text, const std::string& variable, bool lately, int64_t step, int repeat,
               unsigned threads) {
  WhyRow row;
  auto s = load_bench_scenario(text);
  if (!s) return row.failed = true, row;
  sim::Session session(*s->model, *s->world, {.threads = threads, .end = step + 1});
  session.run_until(step + 1);  // to step `step`
  row.interval = session.keyframe_interval();
  const int column = session.model().column(variable);
  if (column < 0) return std::cerr << "bench session: no variable " << variable << "\n", row.failed = true, row;
  for (uint32_t m = 0; lately && m < session.model().module_count(); ++m) {
    const auto values = session.series(m, column, step - 4, step);
    if (!values) return std::cerr << "bench session: no series of module " << m << "\n", row.failed = true, row;
    if (std::adjacent_find(values->begin(), values->end(), std::not_equal_to<>()) == values->end()) continue;
    row.module = m;
    break;
  }
  std::vector<double> seeks, whys, cpus;
  for (int r = 0; r < std::max(1, repeat); ++r) {
    session.seek(0);
    auto start = Clock::now();
    session.seek(step);
    session.state();
    seeks.push_back(1000 * since(start));
    session.seek(0);
    start = Clock::now();
    const double cpu = cpu_seconds();
    const auto cone = sim::why_value(session, row.module, column, step, 3, false, {});
    whys.push_back(1000 * since(start));
    cpus.push_back(1000 * (cpu_seconds() - cpu));
    if (!cone || cone->values.empty()) return std::cerr << "bench session: no cone\n", row.failed = true, row;
    row.origin = cone->values[0].asked.origin;
    row.events = cone->events.size();
    row.messages = cone->messages.size();
  }
  std::sort(seeks.begin(), seeks.end());
  std::sort(whys.begin(), whys.end());
  row.seek_ms = seeks.front();
  row.why_ms = whys.front();
  row.why_median_ms = whys[whys.size() / 2];
  row.why_cpu_ms = *std::min_element(cpus.begin(), cpus.end());
  return row;
}

void print_why(const std::string& label, const std::string& variable, int64_t step, const WhyRow& r, long peak_kib) {
  std::cout << std::fixed << std::setprecision(1) << "why at depth 3, " << label << ", step " << step << ":\n"
            << "  why " << r.module << " " << variable << " " << step << " (origin " << r.origin << ", " << r.events
            << " events, " << r.messages << " messages): " << r.why_ms << " ms (median " << r.why_median_ms
            << "; CPU time " << r.why_cpu_ms << " ms)\n  beside: seek to step " << step << " from step 0: " << r.seek_ms
            << " ms (keyframes every " << r.interval << " steps); why beyond the seek: " << r.why_ms - r.seek_ms
            << " ms (target: <= 100 ms)\n  peak memory: " << double(peak_kib) / 1024 << " MiB\n";
}

// A run of `steps` with the history on and off (best of `repeat` each), then seeks to 40 random
// steps of the history.
HistoryRow history_row(const std::string& text, int64_t steps, int repeat, unsigned threads) {
  HistoryRow row;
  for (int r = 0; r < repeat; ++r)
    for (bool on : {false, true}) {
      if (repeat == 0) break;
      auto s = load_bench_scenario(text);
      if (!s) return row.failed = true, row;
      sim::Session session(
          *s->model, *s->world,
          {.threads = threads, .end = steps, .history_bytes = on ? sim::SessionOptions{}.history_bytes : 0});
      const auto start = Clock::now();
      session.run_until(steps);
      const double seconds = since(start);
      double& best = on ? row.live_on : row.live_off;
      best = r == 0 ? seconds : std::min(best, seconds);
    }
  auto s = load_bench_scenario(text);
  if (!s) return row.failed = true, row;
  sim::Session session(*s->model, *s->world, {.threads = threads, .end = steps});
  session.run_until(steps);
  row.keyframes = static_cast<int64_t>(session.keyframes());
  row.interval = session.keyframe_interval();
  row.history_bytes = session.history_bytes();
  {
    const size_t before = mallinfo2().uordblks;
    const sim::State copy = session.head();
    row.state_bytes_measured = mallinfo2().uordblks - before;
    for (const sim::WatchState& w : copy.watches) {
      for (const watch::RecordBuffer& lane : w.in_flight) row.in_flight_bytes += lane.bytes();
      if (w.agents) row.agent_bytes += w.agents->bytes();
    }
  }
  std::mt19937_64 rng(7);
  std::vector<double> ms;
  for (int i = 0; i < 40; ++i) {
    const int64_t t = static_cast<int64_t>(rng() % static_cast<uint64_t>(steps - 1));
    const auto start = Clock::now();
    session.seek(t);
    session.state();
    ms.push_back(1000 * since(start));
  }
  std::sort(ms.begin(), ms.end());
  row.seek_max_ms = ms.back();
  row.seek_median_ms = ms[ms.size() / 2];
  return row;
}

// A Fig. 6 watchpoint added after `steps` steps, against a run that had it from step 0.
RetroRow retro_row(int64_t steps, unsigned threads, const shell::DetectorFlags& flags) {
  RetroRow row;
  auto with = load_bench_scenario(table1_text("2:2:2:2", &flags));
  auto without = load_bench_scenario(table1_text("2:2:2:2", nullptr));
  if (!with || !without) return row.failed = true, row;
  sim::Session fresh(*with->model, *with->world, {.threads = threads, .history_bytes = 0});
  fresh.run_until(steps);
  row.fresh_matches = fresh.match_count(0);

  sim::HostedWatchpoint watch = with->model->watches[0];
  sim::Session session(*without->model, *without->world, {.threads = threads, .end = steps});
  session.run_until(steps);
  const auto start = Clock::now();
  const auto w = session.set_watch(std::move(watch));
  row.seconds = since(start);
  if (!w) return row.failed = true, row;
  row.matches = session.match_count(*w);
  return row;
}

void print_history(const std::string& label, const HistoryRow& r, long peak_kib, sim::OutputFile* csv) {
  const double kib = 1.0 / 1024;
  std::cout << label << "\n" << std::fixed;
  if (r.live_off > 0)
    std::cout << std::setprecision(3) << "  live run: " << r.live_off << " s without history, " << r.live_on
              << " s with it (" << std::setprecision(1) << 100 * (r.live_on / r.live_off - 1) << "%)\n";
  std::cout << std::setprecision(1) << "  keyframes: " << r.keyframes << ", every " << r.interval << " steps, "
            << r.history_bytes * kib * kib << " MiB estimated, "
            << r.history_bytes * kib / double(std::max<int64_t>(1, r.keyframes))
            << " KiB each; one state measured on the heap: " << r.state_bytes_measured * kib << " KiB, of which "
            << r.in_flight_bytes * kib << " KiB PatternMatchers in flight and " << r.agent_bytes * kib
            << " KiB the agents' histories\n"
            << "  seek to a random step: median " << std::setprecision(2) << r.seek_median_ms << " ms, worst "
            << r.seek_max_ms << " ms (40 seeks)\n"
            << "  peak memory: " << std::setprecision(1) << double(peak_kib) / 1024 << " MiB\n";
  if (csv)
    csv->stream() << '"' << label << "\"," << r.live_off << "," << r.live_on << "," << r.keyframes << "," << r.interval
                  << "," << r.history_bytes << "," << r.state_bytes_measured << "," << r.seek_median_ms << ","
                  << r.seek_max_ms << "," << double(peak_kib) / 1024 << "\n";
}

}  // namespace

// `dwatch session --protocol` as a controller drives it, over pipes to a child dwatch: after 10
// steps of the Table I ensemble, `hash` at the current step written and its answer read back,
// `rounds` times; the milliseconds of each round trip, sorted. Empty when it failed.
std::vector<double> protocol_round_trips(const std::string& scenario_text, int rounds) {
  char path[] = "/tmp/dwatch-bench-protocol-XXXXXX";
  const int fd = ::mkstemp(path);
  if (fd < 0) return {};
  const bool written = ::write(fd, scenario_text.data(), scenario_text.size()) == ssize_t(scenario_text.size());
  ::close(fd);
  std::vector<double> ms;
  int to[2], from[2];
  if (written && ::pipe(to) == 0 && ::pipe(from) == 0) {
    const pid_t child = ::fork();
    if (child == 0) {
      ::dup2(to[0], STDIN_FILENO);
      ::dup2(from[1], STDOUT_FILENO);
      ::close(to[1]);
      ::close(from[0]);
      ::execl("/proc/self/exe", "dwatch", "session", path, "--protocol", static_cast<char*>(nullptr));
      ::_exit(127);
    }
    ::close(to[0]);
    ::close(from[1]);
    FILE* answers = ::fdopen(from[0], "r");
    auto round_trip = [&](const std::string& request) {
      const std::string line = request + "\n";
      if (::write(to[1], line.data(), line.size()) != ssize_t(line.size())) return false;
      char* answer = nullptr;
      size_t size = 0;
      const bool read = ::getline(&answer, &size, answers) > 0 &&
                        std::string_view(answer).find("\"error\"") == std::string_view::npos;
      std::free(answer);
      return read;
    };
    if (child > 0 && answers && round_trip("run 10")) {
      for (int i = 0; i < rounds; ++i) {
        const auto start = Clock::now();
        if (!round_trip("hash")) {
          ms.clear();
          break;
        }
        ms.push_back(since(start) * 1e3);
      }
    }
    ::close(to[1]);
    if (answers) std::fclose(answers);
    if (child > 0) ::waitpid(child, nullptr, 0);
  }
  ::unlink(path);
  std::sort(ms.begin(), ms.end());
  return ms;
}

int bench_session(const BenchArgs& args) {
  std::unique_ptr<sim::OutputFile> csv;
  if (!open_csv(args, "session",
                "row,live_off_s,live_on_s,keyframes,interval,history_bytes,state_bytes,seek_median_ms,seek_max_ms,"
                "peak_mib",
                csv))
    return 2;
  const int repeat = std::min(args.repeat, 3);
  const unsigned threads = args.threads;
  std::cout << "bench session: " << threads << (threads == 1 ? " thread" : " threads") << ", best of " << repeat
            << " live runs\n";
  long peak = 0;

  // `why` on 10,000 modules (issue target: 100 ms beyond the seek to its step).
  const std::string why_cube = "seed = 1\n" + cubic_toml(25, 20, 20);
  WhyRow w;
  if (!in_child(
          [&] {
            return why_row(why_cube + random_vars_toml(parse_tuple("2:2:2:2")) + kAggregationToml, "x1", true, 1000,
                           repeat, threads);
          },
          w, peak) ||
      w.failed)
    return 1;
  print_why("random_vars [2:2:2:2] and aggregation_routing on 10,000 modules (25x20x20), a value changed lately", "x1",
            1000, w, peak);
  if (!in_child(
          [&] {
            return why_row(why_cube + "[[program]]\nname = \"leader_election\"\nbug = true\n", "isLeader", false, 1000,
                           repeat, threads);
          },
          w, peak) ||
      w.failed)
    return 1;
  print_why("leader election on 10,000 modules (25x20x20), module 0's isLeader", "isLeader", 1000, w, peak);

  HistoryRow h;
  if (!in_child([&] { return history_row(table1_text("2:2:2:2", &args.detector), 2000, repeat, threads); }, h, peak) ||
      h.failed)
    return 1;
  print_history("Table I ensemble (10^3, random_vars [2:2:2:2], Fig. 6 distributed), 2,000 steps", h, peak, csv.get());

  if (!in_child([&] { return history_row(kPhysicsElection, 2000, repeat, threads); }, h, peak) || h.failed) return 1;
  print_history("physics: leader election, 1,000 modules (hex 40x25, latched), two_leaders, 2,000 steps", h, peak,
                csv.get());

  RetroRow r;
  if (!in_child([&] { return retro_row(1000, threads, args.detector); }, r, peak) || r.failed) return 1;
  std::cout << "retroactive Fig. 6 (distributed, [2:2:2:2]) over 1,000 steps of 1,000 modules: " << std::fixed
            << std::setprecision(3) << r.seconds << " s, " << r.matches
            << " matches (a run with it from step 0: " << r.fresh_matches << ")"
            << (r.matches == r.fresh_matches ? "" : "  MISMATCH") << "\n";
  if (r.matches != r.fresh_matches) return 1;

  // The protocol's round trip (issue target: 1 ms median).
  const std::vector<double> trips = protocol_round_trips(table1_text("2:2:2:2", &args.detector), 1000);
  if (trips.empty()) {
    std::cerr << "bench session: the protocol's child failed\n";
    return 1;
  }
  std::cout << "session --protocol, 'hash' at the current step of the Table I ensemble (10^3), 1,000 round trips: "
            << std::setprecision(3) << "median " << trips[trips.size() / 2] << " ms, 99th percentile "
            << trips[trips.size() * 99 / 100] << " ms, max " << trips.back() << " ms (target: median <= 1 ms)\n";

  const int64_t long_run = std::max<int64_t>(args.steps, 100'000);
  // One run, with the history (its memory is the figure).
  if (!in_child([&] { return history_row(table1_text("8:4:2:1", &args.detector), long_run, 0, threads); }, h, peak) ||
      h.failed)
    return 1;
  print_history("history memory: Table I ensemble ([8:4:2:1]), " + std::to_string(long_run) + " steps", h, peak,
                csv.get());
  return shell::commit_outputs({csv.get()}) ? 0 : 1;
}

}  // namespace dw::bench
