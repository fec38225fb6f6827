// `dwatch bench lua`: the Lua ports of scenarios/lua/ beside their C++ twins (docs/design.md §11). Each row
// runs the same scenario with the program named (C++) or read from its script (Lua), without a
// watchpoint and without history, in a child process (its peak memory its own):
//   - token_ring on a ring of 1,000 for 1,000 steps;
//   - leader_election and aggregation_routing on the 10^3 cube for 200 steps;
//   - leader_election on the 100^3 cube (50^3 with --quick) for a few steps: memory.
// The figure is microseconds per module-step: the whole step (programs, messages, topology).
#include <iomanip>
#include <iostream>

#include "bench/bench.h"
#include "bench/shipped_files.h"
#include "shell/output_files.h"

namespace dw::bench {
namespace {

struct Workload {
  const char* program;  // the built-in's name; the script is scenarios/lua/<program>.lua
  std::string lattice;  // scenario text
  uint64_t modules;
  int64_t steps;
  double bar_us = 0;  // the bar for the Lua port, µs per module-step (0: none)
};

std::string program_toml(const Workload& w, bool lua) {
  return std::string("[[program]]\n") + (lua ? "script = \"" + shipped_files().lua + "/" + w.program + ".lua\"\n"
                                             : "name = \"" + std::string(w.program) + "\"\n");
}

struct Measured {
  RuntimeRow cpp, lua;
  double us(const RuntimeRow& r, const Workload& w) const {
    return 1e6 * r.seconds / (double(w.modules) * double(w.steps));
  }
};

}  // namespace

int bench_lua(const BenchArgs& args) {
  std::unique_ptr<sim::OutputFile> csv;
  if (!open_csv(args, "lua", "row,language,modules,steps,best_seconds,median_seconds,us_per_module_step,peak_mib", csv))
    return 2;
  const uint32_t big = args.quick ? 50 : 100;
  const std::vector<Workload> speed = {
      {"token_ring", "[lattice]\nkind = \"ring\"\nsize = [1000]\n", 1000, 1000, 1.0},
      {"leader_election", cubic_toml(10, 10, 10), 1000, 200, 2.0},
      {"aggregation_routing", cubic_toml(10, 10, 10), 1000, 200},  // the C++ twin's 3 landmarks
  };
  const Workload memory{"leader_election", cubic_toml(big, big, big), uint64_t(big) * big * big, 3};

  std::cout << "bench lua: the Lua ports (scenarios/lua/) beside their C++ twins, " << args.threads
            << (args.threads == 1 ? " thread" : " threads") << ", no watchpoint\n"
            << std::left << std::setw(34) << "row" << std::right << std::setw(10) << "best s" << std::setw(10)
            << "median s" << std::setw(16) << "us/module-step" << std::setw(10) << "peak MiB" << std::setw(10)
            << "Lua/C++"
            << "\n";
  bool all_met = true;
  auto run = [&](const Workload& w, Measured& m) {
    for (const bool lua : {false, true}) {
      RuntimeRow& r = lua ? m.lua : m.cpp;
      BenchArgs a = args;
      a.steps = w.steps;
      // The memory row runs once: its peak is one run's.
      const bool once = w.modules > 100'000;
      if (!run_runtime_row(w.lattice + program_toml(w, lua), a, once ? 1 : args.repeat, r, Timed::Steps,
                           once ? 0 : 0.5))
        return false;
      const std::string label = std::string(w.program) + (lua ? ".lua" : " (C++)") + ", " + std::to_string(w.modules) +
                                " x " + std::to_string(w.steps);
      const double mib = double(r.peak_kib) / 1024.0;
      std::cout << std::left << std::setw(34) << label << std::right << std::fixed << std::setprecision(3)
                << std::setw(10) << r.seconds << std::setw(10) << r.median_seconds << std::setw(16) << m.us(r, w)
                << std::setw(10) << std::setprecision(1) << mib;
      if (lua) std::cout << std::setw(9) << std::setprecision(1) << m.lua.seconds / m.cpp.seconds << "x";
      std::cout << "\n";
      if (csv)
        csv->stream() << w.program << "," << (lua ? "lua" : "c++") << "," << w.modules << "," << w.steps << ","
                      << r.seconds << "," << r.median_seconds << "," << m.us(r, w) << "," << mib << "\n";
    }
    return true;
  };
  for (const Workload& w : speed) {
    Measured m;
    if (!run(w, m)) return 1;
    if (w.bar_us > 0) {
      const bool met = m.us(m.lua, w) <= w.bar_us;
      all_met = all_met && met;
      std::cout << "  " << w.program << ".lua: " << std::setprecision(3) << m.us(m.lua, w) << " us per module-step, "
                << (met ? "within" : "OVER") << " the bar of " << std::setprecision(1) << w.bar_us << " us\n";
    }
  }
  Measured m;
  if (!run(memory, m)) return 1;
  const double ratio = double(m.lua.peak_kib) / double(m.cpp.peak_kib);
  const bool met = ratio <= 2.0;
  all_met = all_met && met;
  std::cout << "  leader_election.lua on " << memory.modules << " modules: " << std::setprecision(2) << ratio
            << "x the C++ twin's peak memory, " << (met ? "within" : "OVER") << " the bar of 2x\n";
  if (!shell::commit_outputs({csv.get()})) return 1;
  return all_met ? 0 : 1;
}

}  // namespace dw::bench
