#include "scenarios/memory_estimate.h"

#include <algorithm>
#include <fstream>

#include "sim/read_file.h"

namespace dw::scenarios {

uint64_t memory_estimate(uint64_t modules, bool physics, uint64_t history_mb, uint64_t variables) {
  const uint64_t per_module =
      kStaticBytesPerModule + (physics ? kPhysicsBytesPerModule : 0) + variables * kBytesPerVariable;
  return kFixedBytes + modules * per_module + (history_mb << 20);
}

uint64_t memory_limit() {
  uint64_t limit = sim::available_memory();
  // A container's limit: cgroup v2's memory.max less what the group already uses.
  std::ifstream max_file("/sys/fs/cgroup/memory.max"), current_file("/sys/fs/cgroup/memory.current");
  uint64_t max = 0, current = 0;
  if (max_file >> max && current_file >> current && max > current)
    limit = limit == 0 ? max - current : std::min(limit, max - current);
  return limit;
}

std::string memory_refusal(uint64_t modules, bool physics, uint64_t history_mb, uint64_t limit, uint64_t variables) {
  const uint64_t per_module =
      kStaticBytesPerModule + (physics ? kPhysicsBytesPerModule : 0) + variables * kBytesPerVariable;
  return "that is " + std::to_string(modules) + " modules, which need about " +
         sim::size_text(memory_estimate(modules, physics, history_mb, variables)) + " (" + std::to_string(per_module) +
         " bytes per module" + (physics ? ", physics included" : "") +
         (variables > 0 ? ", " + std::to_string(variables) + " variables each" : "") + ", and " +
         std::to_string(history_mb) + " MiB of history); this machine has " + sim::size_text(limit) +
         " available (--no-memory-check tries anyway)";
}

}  // namespace dw::scenarios
