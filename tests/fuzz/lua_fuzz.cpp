// libFuzzer target for host programs in Lua under the sandbox (scenarios/lua_host/lua_program.h,
// scenarios/lua_host/lua_sandbox.h, scenarios/lua_host/lua_watchdog.h; docs/design.md §11): any text is loaded as a
// script and, when it declares itself, stepped for kSteps steps on a line of kModules modules (its
// neighbours, messages and random draws included). A script is code from someone else that dwatch
// runs, so every input must end within the sandbox's limits, whatever it tries (an endless loop
// under pcall, string.rep, backtracking patterns, coroutines, metatables): a hang is a libFuzzer
// timeout and unbounded memory its rss or malloc limit, both findings. The limits are made small
// (kLimits) so that an input that runs into them costs milliseconds.
//
// Each script runs twice, and the runs must agree (docs/design.md §11: what a call does never
// depends on the machine's speed):
//   - with every call counted from its start (patience 0);
//   - as dwatch runs scripts, each call uncounted until the watchdog interrupts it after a
//     millisecond, what it did taken back, and run again counted.
// Both give the same state hash after every step, or fail at the same step and module with the
// same message. A call run counted runs in a state made for it (scenarios/lua_host/lua_state.cpp), so
// nothing earlier runs leave in a state moves where it stops, with two exceptions by design:
//   - time: a call stopped by the wall-clock deadline in either run, and a call the counted run
//     stopped by its budget that the other finished, uncounted, within its patience;
//   - Lua's string-hash seed, drawn anew for every state: when a table with string keys grows
//     follows their collisions, so where a call meets the memory cap can move by an allocation
//     or two. A memory stop in one run may be a budget stop of the same call in the other, or
//     come a little later there (the other run may finish that call).
// Up to the step of the first stop the runs agree in every case. A script that is refused says
// why.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "scenarios/lua_host/lua_program.h"
#include "scenarios/scenario.h"
#include "sim/session.h"

namespace {

using namespace std::chrono_literals;

constexpr uint32_t kModules = 3;  // a line: 0 - 1 - 2
constexpr int64_t kSteps = 2;
// A hundredth of a real script's instruction budget, a 256th of its memory (a Lua state with the
// libraries holds about 40 KiB; a shipped script needs a fraction of the rest), patterns to
// match; a deadline short enough that an input whose every call runs into it stays within
// libFuzzer's timeout. A small cap makes the limits meet early (where they race, if anything
// does) and each input cheap: replaying the corpus takes 2.3 times less than with 1 MiB.
const dw::scenarios::LuaLimits kLimits{
    .instructions = 100'000, .memory_bytes = 1u << 18, .deadline = 50ms, .pattern_steps = 1e6};

// The lattice and the world the scripts run on, loaded once.
dw::scenarios::Scenario& line_of_modules() {
  static dw::scenarios::Scenario line = [] {
    auto loaded = dw::scenarios::load_scenario_text(
        "fuzz.toml",
        "[lattice]\nkind = \"line\"\nsize = [" + std::to_string(kModules) + "]\n[[program]]\nname = \"token_ring\"\n");
    if (auto* errors = std::get_if<std::string>(&loaded)) {
      std::fprintf(stderr, "lua_fuzz: %s", errors->c_str());
      std::abort();
    }
    return std::move(std::get<dw::scenarios::Scenario>(loaded));
  }();
  return line;
}

// What a run of the script did: the state hash after each step it ran through, and the failure
// that stopped it.
struct RunResult {
  std::vector<uint64_t> hashes;
  std::optional<std::string> failure;
  int64_t failed_step = -1;
  uint32_t failed_module = 0;
};

bool mentions(const std::string& text, const char* part) { return text.find(part) != std::string::npos; }
// Whether the script may read what Lua leaves unordered: `pairs` and `next` over string keys
// (docs/lua.md, "Determinism"), whose order follows each Lua state's own hash seed. Two runs of
// such a script may differ, by design.
bool reads_unordered(const std::string& text) {
  for (size_t at = text.find("pairs"); at != std::string::npos; at = text.find("pairs", at + 1))
    if (at == 0 || text[at - 1] != 'i') return true;
  return mentions(text, "next");
}
[[noreturn]] void differ(const char* what, const std::string& counted, const std::string& watched) {
  std::fprintf(stderr, "lua_fuzz: %s\n  counted: %s\n  watched: %s\n", what, counted.c_str(), watched.c_str());
  __builtin_trap();
}
bool past_deadline(const RunResult& r) { return r.failure && mentions(*r.failure, "of wall-clock time"); }
bool over_budget(const RunResult& r) { return r.failure && mentions(*r.failure, "instructions in one call"); }
bool out_of_memory(const RunResult& r) { return r.failure && mentions(*r.failure, "not enough memory"); }
bool over_a_limit(const RunResult& r) { return over_budget(r) || out_of_memory(r); }

// Builds the script's program with `patience` and runs it; the reason when the script is refused
// (or declares what no model can hold), which is never empty.
std::variant<RunResult, std::string> run(const std::string& text, std::chrono::milliseconds patience) {
  namespace sim = dw::sim;
  dw::scenarios::LuaLimits limits = kLimits;
  limits.patience = patience;
  std::string why;
  auto program = dw::scenarios::make_lua_program("fuzz.lua", text, dw::scenarios::ParamValues{}, why, limits);
  if (!program) {
    if (why.empty()) {
      std::fprintf(stderr, "lua_fuzz: a script refused without a reason\n");
      __builtin_trap();
    }
    return why;
  }
  dw::scenarios::Scenario& line = line_of_modules();
  std::vector<std::unique_ptr<const sim::HostProgram>> programs;
  programs.push_back(std::move(program));
  auto built = sim::build_model(line.model->lattice, std::move(programs), {}, line.model->seed);
  if (auto* error = std::get_if<std::string>(&built)) return *error;  // e.g. a variable named twice
  sim::Model& model = *std::get<std::unique_ptr<sim::Model>>(built);
  sim::Session session(model, *line.world, {.threads = 1, .history_bytes = size_t{1} << 16});
  RunResult result;
  try {
    for (int64_t t = 0; t < kSteps; ++t) {
      session.run_until(t + 1);
      result.hashes.push_back(session.hash().whole());
    }
  } catch (const sim::ProgramError& e) {
    result.failure = e.what();
    result.failed_step = e.step;
    result.failed_module = e.module.value_or(UINT32_MAX);
  }
  return result;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const auto counted_run = run(text, 0ms), watched_run = run(text, 1ms);
  if (reads_unordered(text)) return 0;
  const auto* counted = std::get_if<RunResult>(&counted_run);
  const auto* watched = std::get_if<RunResult>(&watched_run);
  if (!counted || !watched) {
    // Loading runs the script's chunk counted in both: the same refusal, but for the deadline.
    const auto* a = std::get_if<std::string>(&counted_run);
    const auto* b = std::get_if<std::string>(&watched_run);
    const bool timed = (a && mentions(*a, "of wall-clock time")) || (b && mentions(*b, "of wall-clock time"));
    if (!timed && (!a || !b || *a != *b))
      differ("a script is refused differently with another patience", a ? *a : "(loaded)", b ? *b : "(loaded)");
    return 0;
  }
  if (past_deadline(*counted) || past_deadline(*watched)) return 0;
  const std::string a = counted->failure.value_or("(ran through)"), b = watched->failure.value_or("(ran through)");
  // The run that stopped first (at an earlier step, or an earlier module of it); a run that ran
  // through stops last.
  const auto stops_at = [](const RunResult& r) {
    return r.failure ? std::pair{r.failed_step, int64_t(r.failed_module)} : std::pair{INT64_MAX, INT64_MAX};
  };
  if (stops_at(*counted) != stops_at(*watched)) {
    // Excused: a memory stop, which may fall a little later in the other run, and a call the
    // counted run stopped by its budget that the watched run finished uncounted. Either way the
    // runs agree up to the step of that stop.
    const RunResult& first = stops_at(*counted) < stops_at(*watched) ? *counted : *watched;
    if (!out_of_memory(first) && !(&first == counted && over_budget(*counted)))
      differ("the counted and the watched run stop at different calls", a, b);
    for (size_t t = 0; t < first.hashes.size(); ++t)
      if (t >= counted->hashes.size() || t >= watched->hashes.size() || counted->hashes[t] != watched->hashes[t])
        differ("the runs differ before the step the first of them stopped in", a, b);
    return 0;
  }
  // The same call stopped in both, by the same message; or by the two limits, the memory cap in
  // one of them: where it meets the cap moves a little, to either side of the budget.
  const bool limits_meet =
      over_a_limit(*counted) && over_a_limit(*watched) && (out_of_memory(*counted) || out_of_memory(*watched));
  if (counted->hashes != watched->hashes || (a != b && !limits_meet))
    differ("the counted and the watched run differ", a, b);
  return 0;
}
