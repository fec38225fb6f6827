// Builds small ensembles step by step for detector tests, and runs a detector over them.
// (watch/ is tested without sim/, so this is the tests' own tiny trace.)
#pragma once

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "watch/make_detector.h"
#include "watch/watchpoint.h"

namespace dw::watch::testing {

using Match = std::pair<int64_t, std::vector<ModuleId>>;  // (t, ids in slot order)

class TestEnsemble {
 public:
  TestEnsemble(uint32_t modules, std::vector<std::string> variables) {
    for (uint32_t m = 0; m < modules; ++m) universe_.module_ids.push_back(m);
    universe_.variables = std::move(variables);
  }

  // Module m is present at step t with these values (absent variables: lacking) and neighbours.
  void set(int64_t t, uint32_t m, std::map<std::string, int64_t> vars, std::vector<uint32_t> nbrs) {
    grow(t);
    Step& s = steps_[static_cast<size_t>(t)];
    s.present[m] = 1;
    s.vars[m] = std::move(vars);
    s.nbrs[m] = std::move(nbrs);
  }
  void grow(int64_t t) {
    while (static_cast<int64_t>(steps_.size()) <= t) {
      Step s;
      s.present.assign(universe_.module_count(), 0);
      s.vars.resize(universe_.module_count());
      s.nbrs.resize(universe_.module_count());
      steps_.push_back(std::move(s));
    }
  }

  const Universe& universe() const { return universe_; }
  int64_t steps() const { return static_cast<int64_t>(steps_.size()); }
  bool present(int64_t t, uint32_t m) const { return t >= 0 && t < steps() && steps_[t].present[m]; }
  const std::vector<uint32_t>& nbrs(int64_t t, uint32_t m) const { return steps_[t].nbrs[m]; }
  // The value, or nullopt when absent, lacking, or outside the run.
  std::optional<int64_t> value(int64_t t, uint32_t m, const std::string& v) const {
    if (!present(t, m)) return std::nullopt;
    auto it = steps_[t].vars[m].find(v);
    if (it == steps_[t].vars[m].end()) return std::nullopt;
    return it->second;
  }

  // Where a frame's arrays live.
  struct FrameData {
    std::vector<int64_t> values;
    std::vector<uint8_t> has;
    std::vector<uint32_t> begin, nbrs;
  };

  // Step t as a detector observes it.
  Frame frame(int64_t t, FrameData& d) const {
    const size_t mc = universe_.module_count(), vc = universe_.variables.size();
    const Step& s = steps_[static_cast<size_t>(t)];
    d.values.assign(mc * vc, 0);
    d.has.assign(mc * vc, 0);
    d.begin.assign(mc + 1, 0);
    d.nbrs.clear();
    for (size_t m = 0; m < mc; ++m) {
      d.begin[m] = static_cast<uint32_t>(d.nbrs.size());
      if (!s.present[m]) continue;
      for (size_t v = 0; v < vc; ++v) {
        auto it = s.vars[m].find(universe_.variables[v]);
        if (it != s.vars[m].end()) {
          d.values[m * vc + v] = it->second;
          d.has[m * vc + v] = 1;
        }
      }
      d.nbrs.insert(d.nbrs.end(), s.nbrs[m].begin(), s.nbrs[m].end());
    }
    d.begin[mc] = static_cast<uint32_t>(d.nbrs.size());
    Frame f;
    f.step = t;
    f.present = s.present;
    f.values = d.values;
    f.has_value = d.has;
    f.nbr_begin = d.begin;
    f.nbrs = d.nbrs;
    f.variable_count = static_cast<uint32_t>(vc);
    return f;
  }

  // Feeds every step to `d`, and once step `at` is observed, clones it (the clone sends its
  // matches to `sink`) and feeds the clone the later steps too; both drain at the end.
  std::unique_ptr<Detector> feed_and_clone(Detector& d, int64_t at, MatchSink sink) const {
    std::unique_ptr<Detector> copy;
    FrameData data;
    for (int64_t t = 0; t < steps(); ++t) {
      const Frame f = frame(t, data);
      d.observe(f);
      if (copy) copy->observe(f);
      if (t == at) {
        copy = d.clone();
        copy->set_sink(std::move(sink));
      }
    }
    d.finish();
    if (copy) copy->finish();
    return copy;
  }

  // Feeds every step to a detector of `algorithm` and returns its matches as a set.
  std::set<Match> run(Algorithm algorithm, const Watchpoint& w, DetectorOptions options = {},
                      DetectorStats* stats = nullptr) const {
    std::set<Match> out;
    const size_t k = static_cast<size_t>(w.program.slot_count());
    int64_t last_t = -1;
    auto detector = make_detector(
        algorithm, w, universe_, options, [&](int64_t t, std::span<const ModuleId> ids, std::span<const Value>) {
          EXPECT_GT(t, last_t) << "each watch step is reported once, in order";
          last_t = t;
          EXPECT_EQ(k == 0 ? ids.size() : ids.size() % k, 0u);
          for (size_t row = 0, i = 0; row < match_rows(ids.size(), k); ++row, i += k) {
            const bool fresh = out.insert({t, std::vector<ModuleId>(ids.begin() + i, ids.begin() + i + k)}).second;
            EXPECT_TRUE(fresh) << "a binding is reported once per step";
          }
        });
    FrameData data;
    for (int64_t t = 0; t < steps(); ++t) detector->observe(frame(t, data));
    detector->finish();
    if (stats) *stats = detector->stats();
    return out;
  }

 private:
  struct Step {
    std::vector<uint8_t> present;
    std::vector<std::map<std::string, int64_t>> vars;
    std::vector<std::vector<uint32_t>> nbrs;
  };
  Universe universe_;
  std::vector<Step> steps_;
};

inline Watchpoint compile_or_die(const std::string& text) {
  auto r = compile_watchpoint("w", SourceText("test", text));
  if (auto* e = std::get_if<CompileError>(&r)) {
    ADD_FAILURE() << e->format();
    std::abort();
  }
  return std::move(std::get<Watchpoint>(r));
}

// Every combination of the three optimizations.
inline std::vector<Optimizations> all_optimization_combinations() {
  std::vector<Optimizations> out;
  for (int bits = 0; bits < 8; ++bits) out.push_back({(bits & 1) != 0, (bits & 2) != 0, (bits & 4) != 0});
  return out;
}

}  // namespace dw::watch::testing
