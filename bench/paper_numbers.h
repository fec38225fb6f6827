// The numbers the paper publishes in its evaluation (§V), in one place: `bench paper` sets its
// measurements beside them (CSV columns, plots, paper.md).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

namespace dw::bench::paper {

// The ensemble of every experiment but Fig. 8: a 10x10x10 cube, 100 steps.
inline constexpr int kModules = 1000;
inline constexpr int kSteps = 100;

// Table I: successful matches and seconds per host-program tuple, 1,000 modules, distributed.
struct Table1Row {
  std::string_view tuple;
  uint64_t matches;
  double seconds;
};
inline constexpr std::array<Table1Row, 5> kTable1{{{"1:1:1:1", 6'233'141, 715},
                                                   {"2:1:1:1", 3'119'538, 358},
                                                   {"2:2:2:2", 394'103, 128},
                                                   {"1:2:4:8", 96'507, 183},
                                                   {"8:4:2:1", 96'390, 32}}};

inline std::optional<Table1Row> table1(std::string_view tuple) {
  for (const Table1Row& r : kTable1)
    if (r.tuple == tuple) return r;
  return std::nullopt;
}

// Table II: the centralized watchpoint's overhead in percent, 1,000 modules, by expression size
// (1..5 slots) and by how often x_i = 0 holds (max_x_i = 100, 8, 2).
struct Frequency {
  std::string_view name;
  int64_t max;
};
inline constexpr std::array<Frequency, 3> kFrequencies{{{"low", 100}, {"medium", 8}, {"high", 2}}};
inline constexpr int kTable2Sizes = 5;
inline constexpr double kTable2[kTable2Sizes][3] = {
    {7.6, 8.6, 3.6}, {25.2, 32.4, 54.4}, {39.2, 33.0, 104.7}, {42.6, 52.0, 369.8}, {23.0, 83.4, 1432.5}};

// Fig. 8: the mean overhead over the medium-intensity workload, 100 to 1,000 modules.
inline constexpr double kFig8CentralizedOverhead = 118;  // percent
inline constexpr double kFig8DistributedOverhead = 105;

// The text's claims (§V-A, §VI).
inline constexpr double kWorstSlowdown = 14;        // "a slowdown of about fourteen times"
inline constexpr double kReasonableOverhead = 100;  // "overhead of 100% or less"
inline constexpr double kTrajectoryTimeRatio = 6;   // [1:2:4:8] "almost 6 times as long as" [8:4:2:1]

}  // namespace dw::bench::paper
