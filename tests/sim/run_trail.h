// What a run leaves behind for comparing two runs: the state hash after each step and every
// match, flattened per watchpoint as (t, slot ids...).
#pragma once

#include <cstdint>
#include <vector>

#include "sim/session.h"

namespace dw::sim::test {

struct Trail {
  std::vector<uint64_t> hashes;               // after each step
  std::vector<uint64_t> runs;                 // the run hash after each step
  std::vector<std::vector<int64_t>> matches;  // per watch: t and ids, flattened
};

inline std::vector<std::vector<int64_t>> flat_matches(const sim::Session& run) {
  std::vector<std::vector<int64_t>> out;
  for (uint32_t w = 0; w < run.watches().size(); ++w) {
    const MatchList& l = run.matches(w);
    const uint32_t k = run.watches()[w].hosted.watchpoint.program.slot_count();
    std::vector<int64_t> flat;
    for (size_t i = 0; i < l.size(); ++i) {
      flat.push_back(l.t[i]);
      for (uint32_t s = 0; s < k; ++s) flat.push_back(l.slots[i * k + s]);
    }
    out.push_back(std::move(flat));
  }
  return out;
}

}  // namespace dw::sim::test
