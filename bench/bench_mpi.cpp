// `dwatch bench mpi`: the million-module ensemble (bench million) run by `dwatch run` over ranks
// as a user runs it, `mpirun -np R dwatch run SCENARIO -j T --stats FILE`, beside the same run in
// one process: its time, the bytes between ranks per step, memory per rank, and whether every
// layout gave the same matches and state hash (docs/design.md §12); then the Bullet world over ranks:
// many bodies moving at once, and a latched lattice, their physics time and memory per rank.
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "bench/bench.h"
#include "bench/bench_child.h"
#include "shell/output_files.h"

namespace dw::bench {
namespace {

namespace fs = std::filesystem;

struct Layout {
  unsigned ranks = 1, threads = 1;
  std::string label() const {
    return std::to_string(ranks) + (ranks == 1 ? " rank x " : " ranks x ") + std::to_string(threads) +
           (threads == 1 ? " thread" : " threads");
  }
};

// One run: what its --stats said, or a null document when it failed (its stderr is passed on).
nlohmann::json run_once(const Layout& l, const fs::path& scenario, const std::string& partition, const fs::path& dir) {
  const fs::path stats = dir / "stats.json", err = dir / "stderr";
  std::vector<std::string> args;
  if (l.ranks > 1) args = {"mpirun", "--oversubscribe", "-np", std::to_string(l.ranks)};
  args.push_back(fs::read_symlink("/proc/self/exe").string());
  for (const char* a : {"run", scenario.c_str(), "--no-progress", "--print", "0", "-j"}) args.emplace_back(a);
  args.push_back(std::to_string(l.threads));
  args.insert(args.end(), {"--partition", partition, "--stats", stats.string()});
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid == 0) {
    end_with_parent(parent, SIGTERM);  // mpirun stops its ranks on SIGTERM
    const int out = ::open("/dev/null", O_WRONLY), error = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (out < 0 || error < 0 || ::dup2(out, STDOUT_FILENO) < 0 || ::dup2(error, STDERR_FILENO) < 0) ::_exit(127);
    ::execvp(argv[0], argv.data());
    ::_exit(127);
  }
  const int spawned = pid < 0 ? errno : 0;
  int status = 0;
  if (spawned != 0 || waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::ifstream e(err);
    std::cerr << "dwatch bench: error: " << args[0] << (spawned != 0 ? " could not be started" : " failed") << "\n"
              << e.rdbuf();
    return nullptr;
  }
  std::ifstream in(stats);
  return nlohmann::json::parse(in, nullptr, false);
}

// demolition.toml grown to a k x k grid of towers (2 x 2 x 5 modules, four cells apart) with k
// heavy balls rolling down its rows at once: bodies torn off and moving all over the ensemble, in
// physics islands that meet and part.
std::string demolition_toml(int k, int steps) {
  const int side = 6 * k - 4;
  std::ostringstream t;
  t << "seed = 1\nsteps = " << steps << "\n[lattice]\nkind = \"cubic\"\nsize = [" << side << ", " << side << ", 5]\n";
  for (int i = 0; i + 1 < k; ++i)
    t << "[[lattice.empty]]\nfrom = [" << 6 * i + 2 << ", 0, 0]\nto = [" << 6 * i + 5 << ", " << side - 1
      << ", 4]\n[[lattice.empty]]\nfrom = [0, " << 6 * i + 2 << ", 0]\nto = [" << side - 1 << ", " << 6 * i + 5
      << ", 4]\n";
  t << "[[program]]\nname = \"body_sense\"\nmoving_speed = 0.2\n"
    << "[[watch]]\nname = \"torn_off\"\nalgorithm = \"distributed\"\naction = \"log\"\n"
    << "text = \"modules(a); (a.peak_nbrs >= 3) and (a.nbrs = 0) and (a.last.nbrs > 0)\"\n"
    << "[physics]\nenabled = true\nbreak_force = 3000\ncontact_threshold = 0.01\n";
  for (int i = 0; i < k; ++i)
    t << "[[physics.prop]]\nshape = \"sphere\"\ndiameter = 2.0\nmass = 200\nposition = [" << 6 * i << ".5, "
      << (i % 2 ? -8 : -5) << ".0, 1.5]\nvelocity = [0, 14.0, 0.5]\n";
  return t.str();
}

// The Bullet world over ranks (docs/design.md §12): many bodies moving at once, each layout's
// physics part of a step (the slowest rank's) and its peak memory per rank, and latched 40^3 and
// 100^3 lattices' peaks per rank, each against one process's; the same matches and state hash on
// every layout, or it fails.
bool bench_mpi_physics(const BenchArgs& args, const fs::path& dir) {
  const fs::path scenario = dir / "demolition.toml", lattice40 = dir / "lattice40.toml",
                 lattice100 = dir / "lattice100.toml";
  std::ofstream(scenario) << demolition_toml(8, 200);
  const auto latched = [](int side, int steps) {
    return "seed = 1\nsteps = " + std::to_string(steps) + "\n[lattice]\nkind = \"cubic\"\nsize = [" +
           std::to_string(side) + ", " + std::to_string(side) + ", " + std::to_string(side) +
           "]\n[[program]]\nname = \"body_sense\"\n[physics]\nenabled = true\n";
  };
  std::ofstream(lattice40) << latched(40, 20);
  std::ofstream(lattice100) << latched(100, 5);
  std::cout << "\nphysics over ranks (each rank steps a run of the islands; contacts and clusters on every rank)\n"
            << "  demolition 8x8: demolition.toml grown to 8 x 8 towers and 8 balls (1,280 modules), 200 steps\n"
            << "  40^3 latched: a 40^3 lattice latched to the ground, resting, 20 steps (100^3: 5 steps)\n"
            << std::left << std::setw(44) << "scenario, layout" << std::right << std::setw(10) << "matches"
            << std::setw(12) << "best s" << std::setw(18) << "physics ms/step" << std::setw(14) << "MiB per rank"
            << std::setw(10) << "of one"
            << "  state hash\n";
  bool same = true;
  for (const auto& [label, path] : {std::pair{"demolition 8x8", scenario}, std::pair{"40^3 latched", lattice40},
                                    std::pair{"100^3 latched", lattice100}}) {
    nlohmann::json first;
    for (const Layout& l : {Layout{1, 1}, Layout{2, 1}, Layout{4, 1}}) {
      double best = 1e300, physics = 1e300;
      nlohmann::json stats;
      for (int i = 0; i < args.repeat; ++i) {
        stats = run_once(l, path, "auto", dir);
        if (stats.is_discarded() || stats.is_null()) return false;
        best = std::min(best, stats["seconds"].get<double>() - stats["setup_seconds"].get<double>());
        physics = std::min(physics, stats["physics_seconds"].get<double>());
      }
      if (first.is_null()) first = stats;
      const bool agrees = stats["matches"] == first["matches"] && stats["state_hash"] == first["state_hash"];
      same &= agrees;
      const double steps = std::max(1.0, stats["steps"].get<double>());
      std::cout << std::left << std::setw(44) << (std::string(label) + ", " + l.label()) << std::right << std::setw(10)
                << stats["matches"].get<uint64_t>() << std::fixed << std::setprecision(3) << std::setw(12) << best
                << std::setprecision(2) << std::setw(18) << 1e3 * physics / steps << std::setprecision(0)
                << std::setw(14) << stats["peak_mib"].get<double>() << std::setw(9)
                << 100 * stats["peak_mib"].get<double>() / first["peak_mib"].get<double>() << "%  "
                << stats["state_hash"].get<std::string>() << (agrees ? "" : "  DIFFERS from one rank") << "\n";
    }
  }
  return same;
}

}  // namespace

int bench_mpi(const BenchArgs& args) {
  const uint32_t size = args.size == 10 ? 100 : args.size;
  // Open MPI refuses to start as root unless told that it may (docs/design.md §12).
  if (geteuid() == 0) {
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 0);
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 0);
  }
  std::error_code ec;
  const fs::path dir = fs::temp_directory_path() / ("dwatch_bench_mpi_" + std::to_string(::getpid()));
  fs::create_directories(dir, ec);
  const fs::path scenario = dir / "million.toml";
  std::ofstream(scenario) << "seed = " << args.seed << "\nsteps = " << args.steps << "\n"
                          << million_toml(size, args.detector);
  struct Cleanup {
    fs::path dir;
    ~Cleanup() {
      std::error_code ignored;
      fs::remove_all(dir, ignored);
    }
  } cleanup{dir};

  std::unique_ptr<sim::OutputFile> csv;
  if (!open_csv(args, "mpi",
                "ranks,threads,matches,state_hash,best_seconds,median_seconds,bytes_per_step,peak_mib,"
                "peak_mib_all_ranks",
                csv))
    return 2;
  const std::vector<Layout> layouts{{1, args.threads == 1 ? 2 : args.threads}, {2, 1}, {2, 2}, {4, 1}};
  const uint64_t modules = uint64_t{size} * size * size;
  std::cout << "bench mpi: " << size << "^3 cube, " << args.steps
            << " steps, random_vars [8:4:2:1] + Fig. 6 live, distributed; dwatch run --partition " << args.partition
            << " under mpirun\n"
            << std::left << std::setw(22) << "layout" << std::right << std::setw(12) << "matches" << std::setw(10)
            << "best s" << std::setw(10) << "median s" << std::setw(16) << "bytes / step" << std::setw(14)
            << "MiB per rank" << std::setw(12) << "MiB, all"
            << "  state hash\n";
  nlohmann::json first;
  double base = 0;
  bool same = true;
  for (const Layout& l : layouts) {
    std::vector<double> times;
    nlohmann::json stats;
    for (int i = 0; i < args.repeat; ++i) {
      stats = run_once(l, scenario, args.partition, dir);
      if (stats.is_discarded() || stats.is_null()) return 1;
      // The steps' time, as before --stats gave the set-up's apart.
      times.push_back(stats["seconds"].get<double>() - stats["setup_seconds"].get<double>());
    }
    std::sort(times.begin(), times.end());
    const double best = times.front(), median = times[times.size() / 2];
    const uint64_t steps = std::max<uint64_t>(1, stats["steps"].get<uint64_t>());
    const uint64_t per_step = stats["bytes_between_ranks"].get<uint64_t>() / steps;
    const double peak = stats["peak_mib"].get<double>(), all = stats["peak_mib_all_ranks"].get<double>();
    if (first.is_null()) {
      first = stats;
      base = best;
    }
    const bool agrees = stats["matches"] == first["matches"] && stats["state_hash"] == first["state_hash"];
    same &= agrees;
    std::cout << std::left << std::setw(22) << l.label() << std::right << std::setw(12)
              << stats["matches"].get<uint64_t>() << std::fixed << std::setprecision(3) << std::setw(10) << best
              << std::setw(10) << median << std::setw(16) << per_step << std::setprecision(0) << std::setw(14) << peak
              << std::setw(12) << all << "  " << stats["state_hash"].get<std::string>()
              << (agrees ? "" : "  DIFFERS from the first row") << std::setprecision(2) << "  (" << best / base
              << "x the first row)\n";
    if (csv)
      csv->stream() << l.ranks << "," << l.threads << "," << stats["matches"].get<uint64_t>() << ","
                    << stats["state_hash"].get<std::string>() << "," << best << "," << median << "," << per_step << ","
                    << peak << "," << all << "\n";
  }
  std::cout << std::setprecision(0)
            << "memory: " << first["peak_mib_all_ranks"].get<double>() * 1048576 / double(modules)
            << " bytes per module in one process\n"
            << (same ? "every layout gave the same matches and state hash\n" : "");
  same &= bench_mpi_physics(args, dir);
  if (!same) std::cerr << "dwatch bench: error: the layouts disagree\n";
  if (!shell::commit_outputs({csv.get()})) return 1;
  return same ? 0 : 1;
}

}  // namespace dw::bench
