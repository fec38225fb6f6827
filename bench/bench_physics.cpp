// `dwatch bench physics` (docs/benchmarks.md): dwatch's physics step beside a plain persistent
// Bullet program (physics/plain_bullet.h) doing the same scene with the same settings in the same
// run, the ratio being the figure (issue 60): unbonded boxes falling, an unbonded pile at rest, a
// bonded cluster falling and at rest, a lattice latched to the ground. Then, unless --quick, what
// a physics world costs beyond a step: setting up and memory, islands over threads, fcc beside
// cubic, and a million modules. Each side of a row runs in a child process of its own.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include "bench/bench.h"
#include "bench/bench_child.h"
#include "bench/runtime_rows.h"
#include "bench/shipped_files.h"
#include "physics/bullet_world.h"
#include "physics/plain_bullet.h"
#include "scenarios/scenario.h"
#include "shell/output_files.h"
#include "sim/session.h"

namespace dw::bench {
namespace {

using physics::BoxMotion;
using physics::PlainBody;
using physics::PlainRun;
using physics::PlainScene;
using physics::Sleeping;

// A side of a row runs at most --repeat times, and stops sooner once its runs add up to this: a
// run of many steps is already a mean over them. The fastest run is the figure.
constexpr double kEnoughSeconds = 2;

// A step of the pile costs tens of the falling boxes' (each box's bounds meet those of up to 26
// others): it runs a twentieth of --steps, which keeps the default run near two minutes.
constexpr int64_t kPileStepsDivisor = 20;

constexpr const char* kSense = "[[program]]\nname = \"body_sense\"\n";

// One row's scene: what it says it measures, its scenario, its steps.
struct Scene {
  std::string label;
  std::string toml;
  int64_t steps = 0;
};

// What one side measured: its fastest run, and where the first run left the boxes. Plain data:
// it comes back from a child process.
struct Side {
  // The first step apart: in it both find every pair of bodies whose bounds meet (a pile's first
  // step costs Bullet two or three of the steps after it).
  double ms_per_step = 0;  // a step after the first, the mean of the fastest run
  double first_ms = 0;     // the first step, the fastest
  uint32_t boxes = 0;
  double energy = 0;   // kinetic energy a box at the end, J (its centre's motion and its spin)
  double deepest = 0;  // the lowest centre's depth below that of a box lying on the ground
  double drop = 0;     // the most any box went down from where it started
  bool failed = false;
};

std::string thousands(uint64_t n) {
  std::string digits = std::to_string(n), out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

std::string edge_text(uint32_t n) { return std::to_string(n) + "^3"; }

// [[lattice.empty]] from..to, inclusive; nothing when the box is empty.
std::string empty_cells(std::array<uint32_t, 3> from, std::array<uint32_t, 3> to) {
  for (size_t i = 0; i < 3; ++i)
    if (from[i] > to[i]) return "";
  const auto list = [](const std::array<uint32_t, 3>& v) {
    return "[" + std::to_string(v[0]) + ", " + std::to_string(v[1]) + ", " + std::to_string(v[2]) + "]";
  };
  return "[[lattice.empty]]\nfrom = " + list(from) + "\nto = " + list(to) + "\n";
}

std::string physics_toml(bool bonds, bool anchor) {
  return std::string("[physics]\nenabled = true\nbonds = ") + (bonds ? "true" : "false") +
         "\nanchor = " + (anchor ? "true" : "false") + "\n";
}

// The scenes of the comparison at edge n (n^3 modules each).
std::vector<Scene> scenes(uint32_t n, int64_t steps) {
  steps = std::max<int64_t>(2, steps);  // the first step is timed apart
  const std::string side = edge_text(n);
  std::vector<Scene> out;
  // n^3 boxes a cell apart every way (every other plane of a (2n - 1)^3 lattice emptied): the
  // lowest layer starts on the ground, each box above falls a module onto the one below, and the
  // columns settle as they land.
  std::string apart = cubic_toml(2 * n - 1, 2 * n - 1, 2 * n - 1);
  const uint32_t last = 2 * n - 2;
  for (uint32_t i = 1; i < last; i += 2)
    apart += empty_cells({i, 0, 0}, {i, last, last}) + empty_cells({0, i, 0}, {last, i, last}) +
             empty_cells({0, 0, i}, {last, last, i});
  out.push_back({"unbonded: " + thousands(uint64_t{n} * n * n) + " boxes a cell apart, falling",
                 apart + kSense + physics_toml(false, false), steps});
  out.push_back({"unbonded: " + side + " pile resting on the ground",
                 cubic_toml(n, n, n) + kSense + physics_toml(false, false),
                 std::max<int64_t>(2, steps / kPileStepsDivisor)});
  // The ground lies under the lowest module: a lone box latched to it, two cells aside, lets the
  // cluster start two module sizes above it. Lattice (n + 2, n, n + 2): the box at (0, 0, 0), the
  // cluster in x 2..n+1, z 2..n+1.
  std::string dropped = cubic_toml(n + 2, n, n + 2) + empty_cells({0, 0, 1}, {1, n - 1, n + 1}) +
                        empty_cells({0, 1, 0}, {1, n - 1, 0}) + empty_cells({1, 0, 0}, {1, 0, 0}) +
                        empty_cells({2, 0, 0}, {n + 1, n - 1, 1});
  out.push_back({"bonded cluster: " + side + " falling from 2 above the ground",
                 dropped + kSense + physics_toml(true, true), steps});
  out.push_back({"bonded cluster: " + side + " resting free on the ground",
                 cubic_toml(n, n, n) + kSense + physics_toml(true, false), steps});
  out.push_back(
      {"latched: " + side + " to the ground, at rest", cubic_toml(n, n, n) + kSense + physics_toml(true, true), steps});
  return out;
}

const physics::BulletWorld* bullet_world(const scenarios::Scenario& s) {
  const auto* world = dynamic_cast<const physics::BulletWorld*>(s.world.get());
  if (!world) std::cerr << "dwatch bench: error: the scene has no physics\n";
  return world;
}

// The end figures of a side, from every box's motion; boxes of `mass` kg, one module across.
void measure_end(std::span<const BoxMotion> boxes, float ground_z, float mass, Side& side) {
  side.boxes = static_cast<uint32_t>(boxes.size());
  const auto squared = [](const sim::Vec3& v) {
    return double(v[0]) * v[0] + double(v[1]) * v[1] + double(v[2]) * v[2];
  };
  double energy = 0;
  side.deepest = -INFINITY;
  side.drop = -INFINITY;
  for (const BoxMotion& b : boxes) {
    // A unit cube's moment of inertia about any axis through its centre is m / 6.
    energy += 0.5 * mass * squared(b.linear) + 0.5 * (mass / 6.0) * squared(b.angular);
    side.deepest = std::max(side.deepest, double(ground_z) + 0.5 - b.end[2]);
    side.drop = std::max(side.drop, double(b.start[2]) - b.end[2]);
  }
  side.energy = boxes.empty() ? 0 : energy / double(boxes.size());
}

// Keeps a run's times if it is the fastest yet (the first run always).
void keep_fastest(int run, double first_seconds, double later_seconds, int64_t later_steps, Side& side) {
  const double first = 1000 * first_seconds, later = 1000 * later_seconds / double(std::max<int64_t>(1, later_steps));
  if (run == 0 || first < side.first_ms) side.first_ms = first;
  if (run == 0 || later < side.ms_per_step) side.ms_per_step = later;
}

// Runs the scene with dwatch: the physics part of a step (World::advance: bodies, contacts, the
// neighbour graph), as `dwatch run`'s physics line gives it.
Side dwatch_side(const std::string& text, const BenchArgs& args, int64_t steps) {
  Side side;
  double total = 0;
  for (int run = 0; run < args.repeat && (run == 0 || total < kEnoughSeconds); ++run) {
    const std::optional<scenarios::Scenario> s = load_bench_scenario(text);
    const physics::BulletWorld* world = s ? bullet_world(*s) : nullptr;
    if (!world) {
      side.failed = true;
      return side;
    }
    sim::Session session(*s->model, *s->world, {.threads = args.threads, .history_bytes = 0});
    session.run_until(1);
    const double first = session.world_seconds();
    const int64_t after_first = session.head().step;
    session.run_until(steps);
    total += session.world_seconds();
    keep_fastest(run, first, session.world_seconds() - first, session.head().step - after_first, side);
    if (run > 0) continue;
    const sim::State& state = session.head();
    std::vector<BoxMotion> boxes;
    for (sim::ModuleId m = 0; m < s->model->module_count(); ++m)
      if (state.present[m])
        boxes.push_back({s->model->lattice.position(m), state.bodies.poses[m].position,
                         state.bodies.velocities[m].linear, state.bodies.velocities[m].angular});
    measure_end(boxes, world->ground_z(), world->settings().module_mass, side);
  }
  return side;
}

// Runs the scene with the plain Bullet program, built from dwatch's first state of it: a body for
// each cluster (a box, or a compound of its members' boxes), each box of an anchored cluster fixed
// on its own, the scenario's settings.
Side bullet_side(const std::string& text, const BenchArgs& args, int64_t steps) {
  Side side;
  const std::optional<scenarios::Scenario> s = load_bench_scenario(text);
  const physics::BulletWorld* world = s ? bullet_world(*s) : nullptr;
  if (!world) {
    side.failed = true;
    return side;
  }
  PlainScene scene{.ground_z = world->ground_z()};
  {
    sim::Session session(*s->model, *s->world, {.threads = 1, .history_bytes = 0});
    const sim::Bodies& b = session.head().bodies;
    for (const sim::Cluster& c : b.clusters) {
      PlainBody cluster;
      for (uint32_t i = c.first; i < c.first + c.count; ++i) {
        const sim::Pose pose = b.poses[b.members[i]];
        if (c.anchored) scene.bodies.push_back({.boxes = {pose}, .fixed = true});
        else cluster.boxes.push_back(pose);
      }
      if (!cluster.boxes.empty()) scene.bodies.push_back(std::move(cluster));
    }
  }
  double total = 0;
  for (int run = 0; run < args.repeat && (run == 0 || total < kEnoughSeconds); ++run) {
    const PlainRun plain =
        physics::run_plain_bullet(scene, world->settings(), physics::sleeping_of(world->settings()), steps);
    total += plain.first_step_seconds + plain.later_steps_seconds;
    keep_fastest(run, plain.first_step_seconds, plain.later_steps_seconds, steps - 1, side);
    if (run == 0) measure_end(plain.boxes, scene.ground_z, world->settings().module_mass, side);
  }
  return side;
}

// The settings both sides share, as a line under the title.
std::string settings_text(const physics::PhysicsSettings& p) {
  std::ostringstream text;
  text << "    plain Bullet: one persistent btDiscreteDynamicsWorld (btDbvtBroadphase, sequential impulses), boxes of "
          "1 (Bullet's margin), a static plane under the lowest module;\n    both: dt "
       << p.dt << " s in " << p.substeps << (p.substeps == 1 ? " substep" : " substeps") << " (up to " << p.max_substeps
       << " while a body could move more than " << p.substep_travel << " in one), gravity " << -p.gravity[2] << ", "
       << p.module_mass << " kg a module, friction " << p.friction << ", restitution " << p.restitution << ", "
       << p.solver_iterations << " solver iterations warm-started with two friction directions a point, ";
  if (physics::sleeping_of(p) == Sleeping::Never) text << "no body ever sleeps\n";
  else
    text << "bodies sleep as Bullet's deactivation has them (" << p.sleep_after << " s slower than " << p.sleep_linear
         << " m/s and " << p.sleep_angular << " rad/s)\n";
  return text.str();
}

// The comparison: each scene with dwatch, then with plain Bullet, and the ratio.
int beside_bullet_rows(const BenchArgs& args, sim::OutputFile* csv) {
  const uint32_t n = args.size == BenchArgs{}.size ? 20 : args.size;
  std::cout << "bench physics: dwatch's physics step (bodies, contacts, the neighbour graph) beside a plain Bullet "
               "program doing the same scene, " +
                   edge_text(n) + " modules, " + threads_text(args) +
                   " (dwatch); ms: a step after the first, the fastest run's mean\n"
            << settings_text(physics::PhysicsSettings{}) << std::left << std::setw(54) << "row" << std::right
            << std::setw(7) << "steps" << std::setw(11) << "dwatch ms" << std::setw(11) << "Bullet ms" << std::setw(15)
            << "dwatch/Bullet"
            << "\n";
  for (const Scene& scene : scenes(n, args.steps)) {
    const std::string text = "seed = " + std::to_string(args.seed) + "\n" + scene.toml;
    Side mine, plain;
    long mine_kib = 0, plain_kib = 0;
    if (!in_child([&] { return dwatch_side(text, args, scene.steps); }, mine, mine_kib) || mine.failed ||
        !in_child([&] { return bullet_side(text, args, scene.steps); }, plain, plain_kib) || plain.failed) {
      std::cerr << "dwatch bench: error: the row '" << scene.label << "' failed\n";
      return 1;
    }
    const double ratio = plain.ms_per_step > 0 ? mine.ms_per_step / plain.ms_per_step : INFINITY;
    std::cout << std::left << std::setw(54) << scene.label << std::right << std::setw(7) << scene.steps << std::fixed
              << std::setprecision(3) << std::setw(11) << mine.ms_per_step << std::setw(11) << plain.ms_per_step
              << std::setprecision(2) << std::setw(14) << ratio << "x\n";
    const double mine_mib = double(mine_kib) / 1024, plain_mib = double(plain_kib) / 1024;
    std::cout << "    dwatch | Bullet: first step " << std::setprecision(3) << mine.first_ms << " | " << plain.first_ms
              << " ms; peak " << std::setprecision(1) << mine_mib << " | " << plain_mib << " MiB\n"
              << "    at the end, dwatch | Bullet: kinetic energy " << std::scientific << std::setprecision(2)
              << mine.energy << " | " << plain.energy << " J a box; deepest centre " << std::fixed
              << std::setprecision(3) << mine.deepest << " | " << plain.deepest
              << " below lying on the ground; largest drop " << mine.drop << " | " << plain.drop << "\n";
    if (csv)
      csv->stream() << '"' << scene.label << "\"," << scene.steps << "," << mine.boxes << "," << mine.ms_per_step << ","
                    << plain.ms_per_step << "," << ratio << "," << mine.first_ms << "," << plain.first_ms << ","
                    << mine.energy << "," << plain.energy << "," << mine.deepest << "," << plain.deepest << ","
                    << mine.drop << "," << plain.drop << "," << mine_mib << "," << plain_mib << "\n";
  }
  return 0;
}

// Set-up and memory, resting 10^3 lattices, islands in parallel, fcc beside cubic. "Free": a
// bonded cluster not latched to the ground.
int physics_rows(const BenchArgs& args, RuntimeTable& table) {
  const std::string threads = threads_text(args);
  RuntimeRow r;
  print_runtime_header("bench physics: set-up, memory, islands and fcc in the Bullet world, " +
                       std::to_string(args.steps) + " steps, body_sense (neighbour count, speed) on every module, " +
                       threads);
  const std::string sense = "[[program]]\nname = \"body_sense\"\n";
  const std::string latched = "[physics]\nenabled = true\n", free = latched + "anchor = false\n";
  auto per_step = [&](const RuntimeRow& x) {
    std::cout << "    " << std::fixed << std::setprecision(3) << 1000 * x.seconds / double(args.steps)
              << " ms per step (physics step, graph rebuild and programs)\n";
  };
  // Setting up a physics world is linear in the modules (physics/pair_cache.h says why it was not).
  // What a module costs: the peaks of 40^3 and 10^3 apart, over the 63,000 modules between.
  std::map<std::pair<uint32_t, bool>, long> peak_kib;
  for (const auto& [n, anchored] :
       {std::pair{10u, true}, {20u, true}, {30u, true}, {40u, true}, {10u, false}, {40u, false}}) {
    const std::string label = "set up and torn down, " + std::to_string(n) + "^3" + (anchored ? "" : " bonded, free");
    if (!print_runtime_row(label, cubic_toml(n, n, n) + sense + (anchored ? latched : free), args, args.repeat, table,
                           r, Timed::SetUp))
      return 1;
    peak_kib[{n, anchored}] = r.peak_kib;
  }
  const auto per_module = [&](bool anchored) {
    return double(peak_kib[{40u, anchored}] - peak_kib[{10u, anchored}]) / (64'000 - 1'000);
  };
  std::cout << std::fixed << std::setprecision(2) << "    memory per module (40^3 peak - 10^3 peak, / 63,000): latched "
            << per_module(true) << " KiB (target 2), bonded but free of the ground " << per_module(false)
            << " KiB (target 4)\n";
  // 20^3 is a row of the comparison with plain Bullet.
  if (!print_runtime_row("resting 10^3, latched to the ground", cubic_toml(10, 10, 10) + sense + latched, args,
                         args.repeat, table, r))
    return 1;
  per_step(r);
  if (!print_runtime_row("resting 10^3 bonded cluster, free", cubic_toml(10, 10, 10) + sense + free, args, args.repeat,
                         table, r))
    return 1;
  per_step(r);
  // Islands in parallel: 64 bonded blocks of 4x4x3, free, resting on the ground a cell apart, each its
  // own island, stepped on one thread and on two.
  std::string blocks = cubic_toml(39, 39, 3);
  for (int i = 4; i < 39; i += 5)
    blocks += "[[lattice.empty]]\nfrom = [" + std::to_string(i) + ", 0, 0]\nto = [" + std::to_string(i) +
              ", 38, 2]\n[[lattice.empty]]\nfrom = [0, " + std::to_string(i) + ", 0]\nto = [38, " + std::to_string(i) +
              ", 2]\n";
  RuntimeRow on_one, on_two;
  BenchArgs two_threads = args;
  two_threads.threads = 2;
  BenchArgs one_thread = args;
  one_thread.threads = 1;
  if (!print_runtime_row("64 bonded blocks apart, free, 1 thread", blocks + sense + free, one_thread, args.repeat,
                         table, on_one) ||
      !print_runtime_row("64 bonded blocks apart, free, 2 threads", blocks + sense + free, two_threads, args.repeat,
                         table, on_two))
    return 1;
  std::cout << std::fixed << std::setprecision(2) << "    physics part: " << 1000 * on_one.world_seconds / args.steps
            << " ms a step on 1 thread, " << 1000 * on_two.world_seconds / args.steps << " ms on 2 ("
            << on_one.world_seconds / on_two.world_seconds << "x)\n";
  // Catoms 3D: an fcc block of 20x20x20 sites (8,000 spheres, 12 neighbours inside) beside the
  // 20^3 cubic one (6 neighbours), latched and resting.
  const std::string fcc = "[lattice]\nkind = \"fcc\"\nsize = [20, 20, 20]\n";
  RuntimeRow cubic_setup, cubic_step, fcc_setup, fcc_step;
  if (!print_runtime_row("set up and torn down, 20^3", cubic_toml(20, 20, 20) + sense + latched, args, args.repeat,
                         table, cubic_setup, Timed::SetUp) ||
      !print_runtime_row("set up and torn down, fcc 20^3", fcc + sense + latched, args, args.repeat, table, fcc_setup,
                         Timed::SetUp) ||
      !print_runtime_row("resting 20^3, latched", cubic_toml(20, 20, 20) + sense + latched, args, args.repeat, table,
                         cubic_step) ||
      !print_runtime_row("resting fcc 20^3, latched", fcc + sense + latched, args, args.repeat, table, fcc_step))
    return 1;
  std::cout << std::fixed << std::setprecision(2) << "    fcc against cubic: set-up "
            << fcc_setup.seconds / cubic_setup.seconds << "x, steps " << fcc_step.seconds / cubic_step.seconds
            << "x (target 1.5)\n";
  return 0;
}

// At scale: a million modules set up, resting and flowing; the watchpoint over
// a physics run of leader election.
int physics_at_scale_rows(const BenchArgs& args, RuntimeTable& table) {
  const std::string sense = "[[program]]\nname = \"body_sense\"\n";
  const std::string latched = "[physics]\nenabled = true\n", free = latched + "anchor = false\n";
  RuntimeRow r;
  // A million modules: a 100^3 block latched to the ground, set up; resting; and with the holes
  // of reconfigure_large.toml flowing through its top layer (1,000 modules set off at step 1,
  // hundreds glide at once after), the physics part of a step apart.
  const auto physics_part = [&](const RuntimeRow& x) {
    std::cout << "    physics part: " << std::fixed << std::setprecision(1)
              << 1000 * x.world_seconds / double(args.steps) << " ms a step (bodies, contacts, the graph)\n";
  };
  if (!print_runtime_row("set up and torn down, 100^3", cubic_toml(100, 100, 100) + sense + latched, args, 1, table, r,
                         Timed::SetUp))
    return 1;
  if (!print_runtime_row("resting 100^3, latched to the ground", cubic_toml(100, 100, 100) + sense + latched, args, 1,
                         table, r))
    return 1;
  physics_part(r);
  std::ifstream flow_file(shipped_files().scenarios + "/reconfigure_large.toml");
  std::stringstream flow;
  flow << flow_file.rdbuf();
  std::string flow_toml = flow.str();
  const size_t seed = flow_toml.find("\nseed = ");  // the bench gives the seed
  flow_toml.erase(seed, flow_toml.find('\n', seed + 1) - seed);
  if (!print_runtime_row("reconfigure_large 100^3 (surface flow)", flow_toml, args, 1, table, r)) return 1;
  physics_part(r);
  // The watchpoint's overhead over a 1,000-module physics run of leader election (hex 40x25).
  const std::string election =
      "[lattice]\nkind = \"hex2d\"\nsize = [40, 25]\n[[program]]\nname = \"leader_election\"\n";
  const std::string two_leaders = watch_toml("two_leaders", "modules(a b c); (a.isLeader = 1) and (c.isLeader = 1)",
                                             watch::Algorithm::Distributed, args.detector);
  for (const auto& [label, physics] : {std::pair{"latched", latched}, std::pair{"bonded, free", free}}) {
    RuntimeRow without, with;
    if (!print_runtime_row(std::string("leader_election 1000, ") + label, election + physics, args, args.repeat, table,
                           without))
      return 1;
    if (!print_runtime_row("  + two_leaders, distributed", election + physics + two_leaders, args, args.repeat, table,
                           with))
      return 1;
    std::cout << std::fixed << std::setprecision(1)
              << "    watchpoint overhead: " << 100 * (with.seconds / without.seconds - 1) << "%\n";
  }
  return 0;
}

}  // namespace

int bench_physics(const BenchArgs& args) {
  std::unique_ptr<sim::OutputFile> beside, rows;
  if (!open_csv(args, "physics",
                "row,steps,modules,dwatch_ms_per_step,bullet_ms_per_step,ratio,dwatch_first_ms,bullet_first_ms,"
                "dwatch_energy_per_box,bullet_energy_per_box,dwatch_deepest,bullet_deepest,dwatch_drop,bullet_drop,"
                "dwatch_peak_mib,bullet_peak_mib",
                beside))
    return 2;
  RuntimeTable table;
  if (!args.quick && !open_csv(args, "physics_runtime", kRuntimeCsvHeader, table.csv)) return 2;
  int status = beside_bullet_rows(args, beside.get());
  if (status == 0 && !args.quick) status = physics_rows(args, table);
  if (status == 0 && !args.quick) status = physics_at_scale_rows(args, table);
  if (!shell::commit_outputs({beside.get(), table.csv.get()})) return 1;
  return status;
}

}  // namespace dw::bench
