// What a scenario will take of the machine's memory, estimated from its size before anything is
// allocated, so that a scenario asking for more than the machine has is refused at once (with the
// estimate and the limit) rather than after minutes of swapping (docs/design.md §5, "Limits").
#pragma once

#include <cstdint>
#include <string>

namespace dw::scenarios {

// Bytes per module, measured with /usr/bin/time on `dwatch run` of a cubic leader election (two
// sizes, the difference divided by the modules between them, so that the libraries' fixed part
// drops out): 50^3 and 100^3 without physics, 20^3 and 30^3 with it. The static part is the
// states, the neighbour graph and the detectors; the physics part is the bodies in the states,
// the clusters and the contact graph's grid and pairs. Measured again when the contact graph
// dropped Bullet's broadphase (100^3 with body_sense: 332 MiB static, 751 MiB latched, 1,040 MiB
// free on the ground: 440 and 730 bytes a module for physics; it was 17 KiB, then 7 KiB).
// Scenarios with more variables or watchpoints take somewhat more: the estimate is for refusing
// what cannot fit, not a promise.
inline constexpr uint64_t kStaticBytesPerModule = 1600;
inline constexpr uint64_t kPhysicsBytesPerModule = 1024;
inline constexpr uint64_t kFixedBytes = 64ull << 20;  // the libraries, the process
// Each variable of each module, beyond the few the figures above hold: its value before and after
// a step and in the first keyframe (measured: 3,000 variables on 10^5 modules took 7.3 GB).
inline constexpr uint64_t kBytesPerVariable = 24;

// The estimate for `modules` modules, with or without physics, `history_mb` MiB of keyframes and
// `variables` variables a module (0 before the programs are known).
uint64_t memory_estimate(uint64_t modules, bool physics, uint64_t history_mb, uint64_t variables = 0);

// What the machine can give this process: MemAvailable, or less under a cgroup's memory.max;
// 0 when unknown.
uint64_t memory_limit();

// "that is N modules, which need about X (B per module[, physics included], and H MiB of
// history); this machine has Y available": the refusal's words.
std::string memory_refusal(uint64_t modules, bool physics, uint64_t history_mb, uint64_t limit, uint64_t variables = 0);

}  // namespace dw::scenarios
