// What bench.h gives every bench: host-program tuples, the Table I ensemble's trace, the watch
// engine timed over a trace's frames, and the CSV file --out asks for.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "bench/bench.h"
#include "shell/output_files.h"
#include "sim/synthetic_trace.h"
#include "watch/make_detector.h"

namespace dw::bench {

std::vector<int64_t> parse_tuple(const std::string& text) {
  std::vector<int64_t> out;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, ':');) {
    size_t used = 0;
    long long v = 0;
    try {
      v = std::stoll(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != part.size() || v < 1) return {};
    out.push_back(v);
  }
  return out.size() == 4 ? out : std::vector<int64_t>{};
}

std::optional<sim::Trace> table1_trace(const BenchArgs& args, const std::string& tuple_text) {
  sim::CubicRandomVars spec;
  spec.maxima = parse_tuple(tuple_text);
  if (spec.maxima.empty()) {
    std::cerr << "dwatch bench: error: tuple '" << tuple_text << "' is not four positive integers like 2:2:2:2\n";
    return std::nullopt;
  }
  spec.nx = spec.ny = spec.nz = args.size;
  spec.steps = args.steps;
  spec.seed = args.seed;
  return sim::make_cubic_random_vars(spec);
}

namespace {

// Runs a fresh detector over every frame `repeat` times (and drains it); the frames are built
// before timing.
EngineRow engine_row(const sim::Trace& trace, const watch::Watchpoint& w, watch::Algorithm a,
                     const watch::DetectorOptions& o, int repeat, const MatchSink* on_match) {
  EngineRow row;
  auto reader = std::get<sim::FrameReader>(sim::FrameReader::make(trace, std::nullopt, sim::default_frame_budget()));
  std::vector<sim::FrameBuffer> buffers(static_cast<size_t>(trace.step_count()));
  std::vector<watch::Frame> frames;
  for (int64_t s = 0; s < trace.step_count(); ++s) frames.push_back(reader.frame(s, buffers[size_t(s)]));
  const size_t slots = w.program.slots.size();
  std::vector<double> times;
  for (int r = 0; r < repeat; ++r) {
    uint64_t matches = 0;
    auto detector =
        watch::make_detector(a, w, reader.universe(), o,
                             [&](int64_t step, std::span<const watch::ModuleId> ids, std::span<const watch::Value>) {
                               matches += watch::match_rows(ids.size(), slots);
                               if (on_match) (*on_match)(step, ids);
                             });
    const auto start = std::chrono::steady_clock::now();
    for (const watch::Frame& f : frames) detector->observe(f);
    detector->finish();
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    const watch::DetectorStats& st = detector->stats();
    row.matches = matches;
    row.created = st.created;
    row.messages = st.messages;
    row.lost = st.lost;
    row.peak_live = st.peak_live;
    row.stopped = st.stopped;
    for (size_t i = 0; i < st.created_by_filled.size() && i < 5; ++i) row.by_filled[i] = st.created_by_filled[i];
  }
  std::sort(times.begin(), times.end());
  row.seconds = times.front();
  row.median_seconds = times[times.size() / 2];
  return row;
}

}  // namespace

EngineRow run_engine_row(const sim::Trace& trace, const watch::Watchpoint& w, watch::Algorithm a,
                         const watch::DetectorOptions& o, int repeat) {
  return engine_row(trace, w, a, o, repeat, nullptr);
}

EngineRow count_engine_row(const sim::Trace& trace, const watch::Watchpoint& w, watch::Algorithm a,
                           const watch::DetectorOptions& o, const MatchSink& on_match) {
  return engine_row(trace, w, a, o, 1, on_match ? &on_match : nullptr);
}

bool open_csv(const BenchArgs& args, const std::string& name, const std::string& header,
              std::unique_ptr<sim::OutputFile>& out) {
  if (args.out_dir.empty()) return true;
  std::error_code ec;
  std::filesystem::create_directories(args.out_dir, ec);
  if (ec) {
    std::cerr << "dwatch: error: --out: cannot make " << args.out_dir << ": " << ec.message() << "\n";
    return false;
  }
  if (!shell::open_output({"--out", (std::filesystem::path(args.out_dir) / (name + ".csv")).string()}, out))
    return false;
  out->stream() << header << "\n";
  return true;
}

}  // namespace dw::bench
