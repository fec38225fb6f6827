// The `dwatch` subcommands (docs/design.md §6). Each returns the process exit code:
// 0 ok, 1 runtime failure, 2 bad input (with a diagnostic on stderr).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

#include "shell/interrupts.h"
#include "sim/rank_exchange.h"

namespace dw::bench {
struct BenchArgs;
}  // namespace dw::bench

namespace dw::app {

// Registers a subcommand on `app`; `run` is set to the function that carries it out once parsed.
void add_check_command(CLI::App& app, std::function<int()>& run);
void add_replay_command(CLI::App& app, std::function<int()>& run);
void add_why_command(CLI::App& app, std::function<int()>& run);  // `why TRACE M VAR T`, docs/files.md
// `ranks`: this process is one rank of a run over several (mpirun, docs/design.md §12), or null.
// `interrupts`: the process's signal watcher, which a long command lets stop it cleanly, or null.
void add_run_command(CLI::App& app, std::function<int()>& run, sim::RankExchange* ranks = nullptr,
                     shell::Interrupts* interrupts = nullptr);
void add_render_command(CLI::App& app, std::function<int()>& run, shell::Interrupts* interrupts = nullptr);
void add_session_command(CLI::App& app, std::function<int()>& run, shell::Interrupts* interrupts = nullptr);
void add_view_command(CLI::App& app, std::function<int()>& run);  // app/view/view_command.cpp
// `bench view` (app/view/bench_view.cpp), which main hands to the bench command (bench/bench_command.h).
int bench_view(const bench::BenchArgs& args);

}  // namespace dw::app
