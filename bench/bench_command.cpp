// `dwatch bench NAME`: the subcommand, its options, and which bench each NAME runs (bench.h lists
// them).
#include "bench/bench_command.h"

#include <memory>
#include <string>
#include <vector>

#include "shell/detector_flags.h"
#include "shell/integer_option.h"
#include "sim/rank_exchange.h"

namespace dw::bench {

void add_bench_command(CLI::App& app, std::function<int()>& run, BenchFunction bench_view) {
  auto* cmd = app.add_subcommand("bench",
                                 "Reproduce the paper's measurements: paper (all of §V, with plots), engine, table1, "
                                 "overhead, million; expressions, shapes, "
                                 "mpi, physics, render, session, view, lua");
  auto args = std::make_shared<BenchArgs>();
  cmd->add_option("name", args->name, "Benchmark to run")
      ->required()
      ->check(CLI::IsMember({"engine", "expressions", "shapes", "table1", "overhead", "million", "mpi", "physics",
                             "paper", "render", "session", "view", "lua"}));
  cmd->add_option("--tuple", args->tuples, "Host-program tuples max_x1:max_x2:max_x3:max_x4 (repeatable)");
  cmd->add_option("--which", args->algorithm, "centralized, distributed or both")
      ->check(CLI::IsMember({"centralized", "distributed", "both"}));
  shell::add_integer_option(*cmd, "--size", args->size, {"size", 1, 200},
                            "Lattice edge (modules per side; million: 100; physics: 20)");
  shell::add_integer_option(*cmd, "--steps", args->steps, {"steps", 1, 1'000'000}, "Steps to run");
  shell::add_integer_option(*cmd, "--seed", args->seed, scenarios::kSeedRange,
                            "Seed of the host program's random variables");
  cmd->add_option("--out", args->out_dir, "Write NAME.csv into this directory");
  shell::add_integer_option(*cmd, "--threads,-j", args->threads, scenarios::kThreadsRange,
                            "Threads stepping modules (table1, overhead, million)");
  shell::add_integer_option(*cmd, "--repeat", args->repeat, {"repeat", 1, 100},
                            "Runs per row (paper: passes over all the rows); the fastest and the median are reported");
  cmd->add_flag("--quick", args->quick,
                "paper: at most 2 passes, 4 sizes for Fig. 8 (under a minute); lua: the memory row at 50^3; "
                "physics: only the rows beside plain Bullet");
  cmd->add_option("--table2-workload", args->table2_workload,
                  "paper: Table II's baseline, random_vars alone (the default) or with aggregation_routing")
      ->check(CLI::IsMember({"random_vars", "aggregation_routing"}));
  cmd->add_option("--partition", args->partition, "mpi: how the ranks share the modules (run --partition)")
      ->check(CLI::IsMember(std::vector<std::string>(sim::kPartitionNames.begin(), sim::kPartitionNames.end())));
  cmd->add_option("--write-trace", args->write_trace, "Also write the synthetic trace (wptrace v1) to FILE");
  shell::add_detector_flags(*cmd, args->detector, /*with_algorithm=*/false);
  cmd->callback([&run, args, cmd, bench_view] {
    const bool tuples_given = cmd->count("--tuple") > 0;
    run = [args, tuples_given, bench_view] {
      if (args->name == "engine") return bench_engine(*args);
      if (args->name == "shapes") return bench_shapes(*args, tuples_given);
      if (args->name == "expressions") return bench_expressions(*args, tuples_given);
      if (args->name == "paper") return bench_paper(*args);
      if (args->name == "render") return bench_render(*args);
      if (args->name == "session") return bench_session(*args);
      if (args->name == "view") return bench_view(*args);
      if (args->name == "lua") return bench_lua(*args);
      if (args->name == "mpi") return bench_mpi(*args);
      return bench_runtime(*args);
    };
  });
}

}  // namespace dw::bench
