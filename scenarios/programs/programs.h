// The built-in host programs, each a distributed algorithm written against the host-program API
// (sim/host_program.h), and the table that finds them by name for scenario files.
#pragma once

#include <algorithm>
#include <memory>
#include <span>
#include <string_view>

#include "scenarios/table_reader.h"
#include "sim/host_program.h"
#include "sim/lattice.h"

namespace dw::scenarios {

// What a program may know about the ensemble it is built for.
struct ProgramSetup {
  const sim::LatticeSpec& lattice;
  uint32_t module_count;              // lattice cells: module ids are 0..module_count-1
  std::span<const uint8_t> occupied;  // per cell: 0 when left empty (no module)
  uint32_t present_count() const { return static_cast<uint32_t>(std::count(occupied.begin(), occupied.end(), 1)); }
};

// Reads the program's parameters from its [[program]] table (reporting mistakes there) and
// builds it; nullptr when a parameter was wrong.
using ProgramFactory = std::unique_ptr<const sim::HostProgram> (*)(TableReader& params, const ProgramSetup& setup);

struct ProgramInfo {
  std::string_view name;
  std::string_view summary;
  ProgramFactory make;
};

std::span<const ProgramInfo> builtin_programs();
const ProgramInfo* find_program(std::string_view name);

// The factories, one per file.
std::unique_ptr<const sim::HostProgram> make_random_vars(TableReader& params, const ProgramSetup& setup);
std::unique_ptr<const sim::HostProgram> make_leader_election(TableReader& params, const ProgramSetup& setup);
std::unique_ptr<const sim::HostProgram> make_token_ring(TableReader& params, const ProgramSetup& setup);
std::unique_ptr<const sim::HostProgram> make_aggregation_routing(TableReader& params, const ProgramSetup& setup);
std::unique_ptr<const sim::HostProgram> make_body_sense(TableReader& params, const ProgramSetup& setup);
std::unique_ptr<const sim::HostProgram> make_slide(TableReader& params, const ProgramSetup& setup);
std::unique_ptr<const sim::HostProgram> make_surface_flow(TableReader& params, const ProgramSetup& setup);

}  // namespace dw::scenarios
