// What the runtime benches share (bench_runtime.cpp: table1, overhead, million; bench_physics.cpp:
// physics): a scenario run as a row, printed under a header and written to the bench's CSV file.
#pragma once

#include <memory>
#include <string>

#include "bench/bench.h"
#include "sim/output_file.h"

namespace dw::bench {

// The CSV header of a table of runtime rows.
inline constexpr const char* kRuntimeCsvHeader =
    "row,matches,created,messages,best_seconds,median_seconds,peak_mib,stopped";

struct RuntimeTable {
  std::unique_ptr<sim::OutputFile> csv;  // --out DIR: DIR/NAME.csv
  bool stopped = false;                  // some row's watch reached its budget
};

// Runs one row in a child process (run_runtime_row) and prints it; false when it failed.
bool print_runtime_row(const std::string& label, const std::string& toml, const BenchArgs& args, int repeat,
                       RuntimeTable& table, RuntimeRow& out, Timed timed = Timed::Steps);
// The title, then the column heads of print_runtime_row.
void print_runtime_header(const std::string& title);
// "1 thread", "4 threads": how many step the modules.
std::string threads_text(const BenchArgs& args);

// bench physics (bench_physics.cpp): dwatch's physics step beside a plain Bullet program, then
// set-up, memory, islands and the million-module rows.
int bench_physics(const BenchArgs& args);

}  // namespace dw::bench
