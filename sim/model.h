// What a scenario fixes for a run (docs/design.md §2): the modules and their lattice, the host programs
// with their parameters, the variable table, the compiled watchpoints. Const while a run goes on;
// everything that changes is in State.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "sim/host_program.h"
#include "sim/lattice.h"
#include "sim/watch_spec.h"
#include "watch/detector.h"
#include "watch/frame.h"
#include "watch/watchpoint.h"

namespace dw::sim {

struct Model {
  Lattice lattice;
  std::vector<std::unique_ptr<const HostProgram>> programs;  // run side by side, in this order
  std::vector<uint32_t> program_base;                        // the column of each program's first variable
  watch::Universe universe;                                  // module ids 0..M-1; variable names in column order
  std::vector<int64_t> initial_values;                       // per column
  std::vector<HostedWatchpoint> watches;
  uint64_t seed = 1;
  // What the messages sent in one step may take in one process, in bytes (each message's header
  // and words); 0: no limit. A program sending without end would otherwise take the machine's
  // memory before its step ended. The loader sets it from what the machine has beyond the
  // scenario's memory estimate; a step going past it stops the run (Runtime::step).
  uint64_t message_bytes_per_step = 0;

  uint32_t module_count() const { return universe.module_count(); }
  uint32_t variable_count() const { return static_cast<uint32_t>(universe.variables.size()); }
  uint32_t program_count() const { return static_cast<uint32_t>(programs.size()); }
  // The column of a variable, or -1.
  int column(std::string_view name) const;
};

// Builds the model; the variable table is every program's variables in program order. Two
// programs declaring the same variable is an error (returned as a message). The model must not
// move afterwards: detectors keep references into it, hence the unique_ptr.
std::variant<std::unique_ptr<Model>, std::string> build_model(Lattice lattice,
                                                              std::vector<std::unique_ptr<const HostProgram>> programs,
                                                              std::vector<HostedWatchpoint> watches, uint64_t seed);

}  // namespace dw::sim
