// `dwatch bench`: the subcommand, registered by main beside the others (app/cli/commands.h).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

#include "bench/bench.h"

namespace dw::bench {

// A bench run by its arguments; its exit code.
using BenchFunction = std::function<int(const BenchArgs&)>;

// Registers `bench` on `app`; `run` is set to the bench it names once parsed. `bench_view` is
// `bench view`, the window's (app/view/bench_view.cpp): it needs a display and Dear ImGui, which
// stay in app/.
void add_bench_command(CLI::App& app, std::function<int()>& run, BenchFunction bench_view);

}  // namespace dw::bench
