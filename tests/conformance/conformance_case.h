// Reading a conformance case (tests/conformance/, tests/conformance_shapes/) and replaying its
// trace through a detector, as `dwatch replay` does.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "sim/trace.h"
#include "watch/make_detector.h"
#include "watch/watchpoint.h"

namespace dw::testing {

namespace fs = std::filesystem;
// (t, slots by name in slot order)
using CaseMatch = std::pair<int64_t, std::vector<std::pair<std::string, uint32_t>>>;

inline std::vector<fs::path> case_dirs(const fs::path& root) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(root))
    if (e.is_directory()) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline std::set<CaseMatch> expected_matches(const fs::path& file) {
  std::set<CaseMatch> out;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) {
    if (line.empty()) continue;
    // nlohmann's ordered_json keeps the slots in the file's order, which is slot order.
    const auto j = nlohmann::ordered_json::parse(line);
    CaseMatch m{j["t"].get<int64_t>(), {}};
    for (const auto& [slot, id] : j["slots"].items()) m.second.emplace_back(slot, id.get<uint32_t>());
    out.insert(std::move(m));
  }
  return out;
}

// A case's trace and watchpoint, ready to replay.
struct LoadedCase {
  sim::Trace trace;
  watch::Watchpoint watchpoint;
};

inline LoadedCase load_case(const fs::path& dir) {
  auto trace = sim::read_trace((dir / "trace.jsonl").string());
  EXPECT_TRUE(std::holds_alternative<sim::Trace>(trace));
  auto compiled = watch::compile_watchpoint(dir.filename().string(),
                                            watch::SourceText((dir / "watch.txt").string(), slurp(dir / "watch.txt")));
  EXPECT_TRUE(std::holds_alternative<watch::Watchpoint>(compiled));
  return {std::get<sim::Trace>(std::move(trace)), std::get<watch::Watchpoint>(std::move(compiled))};
}

// Replays the case through one detector (frames over what the watchpoint reads, as `dwatch
// replay` makes them; the detector drains at the end) and returns its matches.
inline std::set<CaseMatch> replay_case(const LoadedCase& c, watch::Algorithm algorithm, watch::DetectorOptions o,
                                       watch::DetectorStats* stats = nullptr) {
  const watch::Watchpoint& w = c.watchpoint;
  auto reader =
      std::get<sim::FrameReader>(sim::FrameReader::make(c.trace, w.program.variables, sim::default_frame_budget()));
  std::set<CaseMatch> got;
  auto d = watch::make_detector(algorithm, w, reader.universe(), o,
                                [&](int64_t t, std::span<const watch::ModuleId> ids, std::span<const watch::Value>) {
                                  const size_t k = w.program.slot_names.size();
                                  for (size_t row = 0, i = 0; row < watch::match_rows(ids.size(), k); ++row, i += k) {
                                    CaseMatch m{t, {}};
                                    for (size_t s = 0; s < k; ++s)
                                      m.second.emplace_back(w.program.slot_names[s], ids[i + s]);
                                    EXPECT_TRUE(got.insert(std::move(m)).second) << "a match reported twice";
                                  }
                                });
  for (int64_t s = 0; s < c.trace.step_count(); ++s) d->observe(reader.frame(s));
  d->finish();
  if (stats) *stats = d->stats();
  return got;
}

inline watch::Optimizations optimizations_from_bits(int bits) {
  return {(bits & 1) != 0, (bits & 2) != 0, (bits & 4) != 0};
}

}  // namespace dw::testing
