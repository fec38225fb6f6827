// libFuzzer target for the session language (shell/shell.h, docs/design.md §7a): any script
// text is parsed a line at a time with Shell::parse, as `dwatch session` parses it, and
// every command that parsed is carried out with Shell::execute on a small scenario. A
// script is the debugger's whole input surface (the window sends the same commands), and each
// command moves a cursor over a history that is kept as keyframes and re-simulated on demand:
// beyond "no crash, no hang, no sanitizer report", the target checks what a user relies on:
//   - a line that does not parse has one diagnostic or more, each formatted; one that parsed never
//     makes execute throw, and the commands that cannot fail (hash, state, seek to a simulated
//     step, ...) do not; a step or run fails only with a program's failure;
//   - every answer can be written as JSON, as `dwatch session` prints it;
//   - the cursor lands where the command says: `seek T` on T, `step`/`run` on their target or on
//     the step of the pause that stopped them;
//   - the simulation's hash of a step is the same however the step was reached (simulated first,
//     restored from a keyframe after a seek, re-simulated after a watchpoint was added), until an
//     intervention, a reload or a watchpoint with actions changes that branch's past or future;
//   - a recorded trace reads back with every step; a saved scenario loads again and gives the
//     session's simulation hash at the session's current step.
//
// Budgets, stated so that one input stays in the milliseconds: the input's first line
// `# scenario: NAME` (as in tests/shell/session_cases) picks one of a few scenarios shrunk to a
// handful of modules, loaded once; no command takes the cursor past step kLastStep (a step or run
// asking for more stops there), a watchpoint has at most kMaxSlots slots and a lag of at most
// kMaxLag (others are skipped), and at most kMaxCommands commands (kMaxWatches of them `watch`)
// run per input.
// A line `# max-live-all: N` (N from 1 to 10^6) gives the whole run's PatternMatcher budget, so
// that watchpoints that explode meet it within the step budget.
// `render` is skipped (the view's own tests draw); `record` and `save` write into a temporary
// folder whatever FILE the script names, so that no input writes into the source tree, but for
// /dev/full, written as named (every write fails: the command must answer so). The file's own
// name is kept at the end of the temporary's, its bytes as given, so that a name the session
// should have refused would still reach the answers. Findings' reproducers stay in
// tests/fuzz/session_corpus/finding_*.
#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "scenarios/scenario.h"
#include "shell/options.h"
#include "shell/shell.h"
#include "sim/read_file.h"
#include "sim/session.h"
#include "sim/trace.h"
#include "tests/fuzz/small_scenarios.h"
#include "watch/diagnostic.h"

namespace {

namespace fs = std::filesystem;
using dw::shell::Command;
using Kind = Command::Kind;

constexpr int64_t kLastStep = 32;
constexpr int64_t kMaxLag = 8;
constexpr int kMaxSlots = 3;
constexpr size_t kMaxCommands = 16;
constexpr size_t kMaxWatches = 4;
// Small enough that the keyframe interval doubles within kLastStep steps: seeks then restore from
// a keyframe and step on, which the hash check compares with the first simulation.
constexpr size_t kHistoryBytes = size_t{16} << 10;

using dw::fuzz::kScenarios;
constexpr size_t kScenarioCount = std::size(kScenarios);

// A scenario loaded once: a session keeps its own watchpoints and never changes the model, so
// every input starts from the scenario as loaded.
dw::scenarios::Scenario& loaded_scenario(size_t index) {
  static std::optional<dw::scenarios::Scenario> loaded[kScenarioCount];
  if (!loaded[index]) {
    auto made = dw::scenarios::load_scenario_text(DWATCH_SCENARIOS_DIR "/fuzz_session.toml", kScenarios[index].toml);
    if (auto* errors = std::get_if<std::string>(&made)) {
      std::fprintf(stderr, "session_fuzz: scenario %zu: %s", index, errors->c_str());
      std::abort();
    }
    loaded[index].emplace(std::get<dw::scenarios::Scenario>(std::move(made)));
  }
  return *loaded[index];
}

// The scenario a script's first line names (`# scenario: NAME`), else the token ring.
size_t scenario_named_by(std::string_view script) {
  constexpr std::string_view kHeader = "# scenario:";
  if (script.substr(0, kHeader.size()) != kHeader) return 0;
  std::string_view name = script.substr(kHeader.size());
  name = name.substr(0, name.find('\n'));
  while (!name.empty() && (name.front() == ' ' || name.front() == '\t')) name.remove_prefix(1);
  while (!name.empty() && (name.back() == ' ' || name.back() == '\t' || name.back() == '\r')) name.remove_suffix(1);
  for (size_t i = 0; i < kScenarioCount; ++i)
    if (kScenarios[i].name == name) return i;
  return 0;
}

// The run budget a line `# max-live-all: N` gives, else the session's own.
uint64_t run_budget_named_by(std::string_view script) {
  constexpr std::string_view kHeader = "# max-live-all:";
  for (size_t at = 0; at < script.size();) {
    if (script.substr(at, kHeader.size()) == kHeader) {
      uint64_t n = 0;
      for (size_t i = at + kHeader.size(); i < script.size() && n <= 1'000'000; ++i) {
        if (script[i] == ' ') continue;
        if (script[i] < '0' || script[i] > '9') break;
        n = n * 10 + uint64_t(script[i] - '0');
      }
      if (n >= 1 && n <= 1'000'000) return n;
    }
    const size_t newline = script.find('\n', at);
    if (newline == std::string_view::npos) break;
    at = newline + 1;
  }
  return dw::sim::kDefaultRunBudget;
}

// The folder `record` and `save` write into, made once and removed at exit.
class OutputFolder {
 public:
  OutputFolder() {
    std::string pattern = (fs::temp_directory_path() / "dwatch_session_fuzz.XXXXXX").string();
    if (!::mkdtemp(pattern.data())) std::abort();
    path_ = pattern;
  }
  ~OutputFolder() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  const fs::path& path() const { return path_; }
  // Empties it: each input starts with no file from the one before.
  void clear() const {
    std::error_code ignored;
    for (const auto& entry : fs::directory_iterator(path_, ignored)) fs::remove_all(entry.path(), ignored);
  }

 private:
  fs::path path_;
};

bool has_actions(const dw::sim::Session& session) {
  for (uint32_t w = 0; w < session.watches().size(); ++w)
    if (!session.watches()[w].hosted.watchpoint.program.actions.empty()) return true;
  return false;
}

// Brings the command within the budgets above: a step or run that would go past kLastStep stops
// there instead; false for a command that cannot run within them (skipped).
bool fit_budget(Command& c, const dw::sim::Session& session, size_t watches_run) {
  switch (c.kind) {
    case Kind::Step:
      if (session.current() + *c.number > kLastStep) c.number = kLastStep - session.current();
      return *c.number >= 1;
    case Kind::Run:
    case Kind::Continue:
      if (c.number && *c.number > kLastStep) c.number = kLastStep;
      return c.number || std::max(session.end() - 1, session.current()) <= kLastStep;
    case Kind::Watch:
      return watches_run < kMaxWatches && c.watch->lag() <= kMaxLag &&
             c.watch->watchpoint.program.slot_count() <= kMaxSlots;
    case Kind::Render: return false;
    default: return true;
  }
}

// A failure of the check: the input is the finding.
[[noreturn]] void fail(const char* what, const std::string& detail = "") {
  std::fprintf(stderr, "session_fuzz: %s%s%s\n", what, detail.empty() ? "" : ": ", detail.c_str());
  __builtin_trap();
}

// The saved scenario loads again and, run to step t, gives `simulation` as its simulation hash.
void check_saved(const std::string& path, int64_t t, uint64_t simulation) {
  auto reloaded = dw::scenarios::load_scenario(path);
  if (auto* errors = std::get_if<std::string>(&reloaded)) {
    std::string error;
    fail("a saved scenario does not load again", *errors + "\n" + dw::sim::read_file(path, &error).value_or(error));
  }
  dw::scenarios::Scenario& s = std::get<dw::scenarios::Scenario>(reloaded);
  dw::sim::Session again(*s.model, *s.world, {.threads = 1, .end = s.steps, .events = s.events});
  again.decide(t);
  if (!again.seek(t) || again.hash().simulation != simulation)
    fail("a saved scenario does not give the session's state at its current step", std::to_string(t));
}

// A recorded trace reads back with every step of the session's history.
void check_recorded(const std::string& path, int64_t latest) {
  std::string error;
  const auto text = dw::sim::read_file(path, &error);
  if (!text) fail("record wrote no file", error);
  auto read = dw::sim::read_trace_text(path, *text);
  if (auto* errors = std::get_if<std::vector<dw::sim::TraceError>>(&read))
    fail("a recorded trace does not read back", errors->empty() ? "" : errors->front().format());
  if (latest >= 0 && std::get<dw::sim::Trace>(read).step_count() != latest + 1)
    fail("a recorded trace does not hold every step");
}

// What a command's checks need to know of the session before it ran.
struct Before {
  int64_t current = 0, latest = 0;
  bool actions = false;             // a watchpoint had actions
  bool named_watch_exists = false;  // the command names a watchpoint (run --to-match, action, ...) there was
  bool named_watch_counts = false;  // ... and it counts its matches
};

Before before(const Command& c, const dw::sim::Session& session) {
  Before b{.current = session.current(), .latest = session.latest(), .actions = has_actions(session)};
  b.named_watch_exists = !c.name.empty() && session.watch_index(c.name) >= 0;
  b.named_watch_counts =
      b.named_watch_exists && session.watches()[static_cast<uint32_t>(session.watch_index(c.name))].hosted.action ==
                                  dw::sim::MatchAction::Count;
  return b;
}

// The one output written as the script names it: no write to it succeeds.
constexpr std::string_view kFull = "/dev/full";

// Whether the command may fail, as the session stood before it: only with a program's failure, a
// name it does not know, a step not simulated yet, or what an intervention or a file may meet.
bool may_fail(const Command& c, const dw::sim::Session& session, const Before& before) {
  switch (c.kind) {
    case Kind::Step:
    case Kind::Continue: return session.failure().has_value();
    case Kind::Run:
      return session.failure().has_value() ||
             (!c.name.empty() && (!before.named_watch_exists || before.named_watch_counts));
    case Kind::Action: return !before.named_watch_exists;
    case Kind::Seek: return *c.number > before.latest;
    case Kind::Unwatch: return !before.named_watch_exists;
    case Kind::Matches: return !c.name.empty() && !before.named_watch_exists;
    case Kind::Set:
    case Kind::Remove:
    case Kind::Push:
    case Kind::Reload: return true;  // a module already removed; a script unchanged
    case Kind::Watch:
    case Kind::State:
    case Kind::Hash:
    case Kind::Record: return c.name == kFull;
    case Kind::Interventions:
    case Kind::Status:
    case Kind::Help: return false;
    default: return true;  // save: FILE may exist
  }
}

// The answer can be written, and the cursor is where the command says; a recorded trace and a
// saved scenario read back. `simulation_at` forgets the steps a new branch or actions changed.
void check_answer(const Command& c, const nlohmann::ordered_json& answer, dw::sim::Session& session,
                  const Before& before, std::map<int64_t, uint64_t>& simulation_at) {
  if (!answer.contains("cmd")) fail("an answer does not name its command");
  try {
    (void)answer.dump();  // as `dwatch session` writes it
  } catch (const std::exception& e) {
    fail("an answer cannot be written", e.what());
  }
  if (answer.contains("current") && answer["current"] != session.current())
    fail("an answer's current step is not the session's");
  switch (c.kind) {
    case Kind::Seek:
      if (session.current() != *c.number) fail("seek T did not make T current");
      break;
    case Kind::Step:
    case Kind::Run:
    case Kind::Continue: {
      const int64_t target = c.kind == Kind::Step ? before.current + *c.number
                             : c.number           ? *c.number
                                                  : std::max(session.end() - 1, before.current);
      const bool matched = answer.contains("matched") && !answer["matched"].is_null();
      const nlohmann::ordered_json& stop = matched ? answer["matched"] : answer["paused"];
      if (stop.is_null()) {
        if (session.current() != std::max(before.current, target)) fail("a run did not reach its target");
      } else if (stop["t"] != session.current() || session.current() <= before.current || session.current() > target) {
        fail("a run paused off the pause's step");
      }
      if (matched) {
        const auto w = static_cast<uint32_t>(session.watch_index(c.name));
        const auto [first, last] = session.matches(w).at(session.current());
        if (first == last) fail("a run to a match stopped on a step without one");
      }
      break;
    }
    case Kind::Action:
      if (session.watches()[static_cast<uint32_t>(session.watch_index(c.name))].hosted.action != c.action)
        fail("action W A did not change what W does");
      break;
    case Kind::Set:
    case Kind::Remove:
    case Kind::Push:
    case Kind::Reload:
      // The future after the current step is another branch's, simulated again only as far as every
      // watchpoint needs to decide the current step again (Session::decide_again, design §7).
      simulation_at.erase(simulation_at.upper_bound(session.current()), simulation_at.end());
      {
        int64_t lag = 0;
        for (uint32_t w = 0; w < session.watches().size(); ++w) lag = std::max(lag, session.watches()[w].hosted.lag());
        if (session.latest() > session.current() + lag) fail("an intervention kept the future");
      }
      break;
    case Kind::Watch:
    case Kind::Unwatch:
      // Actions change the states themselves: the whole history is another.
      if (before.actions || has_actions(session)) simulation_at.clear();
      break;
    case Kind::Record: check_recorded(c.name, session.latest()); break;
    default: break;
  }
  if (answer.contains("save")) check_saved(c.name, session.current(), session.hash().simulation);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  namespace sim = dw::sim;
  static const OutputFolder outputs;
  const std::string text(reinterpret_cast<const char*>(data), size);
  dw::scenarios::Scenario& scenario = loaded_scenario(scenario_named_by(text));
  sim::SessionOptions options = dw::shell::session_options(scenario, {});
  options.threads = 1;
  options.history_bytes = kHistoryBytes;
  options.run_live_budget = run_budget_named_by(text);
  {
    sim::Session session(*scenario.model, *scenario.world, options);
    dw::shell::Shell shell(scenario, session);
    const dw::watch::SourceText source("fuzz.session", text);
    std::map<int64_t, uint64_t> simulation_at;  // the simulation hash of each step seen, on this branch
    std::map<std::string, std::string> files;   // FILE as the script names it -> in the output folder
    size_t executed = 0, watches_run = 0;
    uint32_t line = 1;
    for (size_t begin = 0; begin < text.size() && executed < kMaxCommands; ++line) {
      auto parsed = shell.parse(source, static_cast<uint32_t>(begin), line);
      const size_t newline = text.find('\n', begin);
      begin = newline == std::string::npos ? text.size() : newline + 1;
      if (auto* mistakes = std::get_if<std::vector<dw::watch::Diagnostic>>(&parsed)) {
        if (mistakes->empty() || dw::watch::format_diagnostics(source, *mistakes).empty())
          fail("a line that does not parse has no diagnostic");
        continue;
      }
      std::optional<Command>& command = std::get<std::optional<Command>>(parsed);
      if (!command) continue;
      Command& c = *command;
      if (c.line != line) fail("a command names another line");
      if (!fit_budget(c, session, watches_run)) continue;
      // record FILE, save FILE: FILE goes to the output folder ("-" is refused by save itself).
      const bool writes = (c.kind == Kind::Record || c.kind == Kind::Save) &&
                          (c.kind == Kind::Record || c.name != "-") && c.name != kFull;
      if (writes) {
        auto [it, added] = files.try_emplace(c.name, "");
        if (added) {
          // At most 64 bytes of it (a long name would be too long for the folder), cut between
          // two characters: a cut inside one would make the answer's bytes not UTF-8.
          std::string name = fs::path(c.name).filename().string();
          size_t cut = std::min<size_t>(name.size(), 64);
          while (cut > 0 && cut < name.size() && (uint8_t(name[cut]) & 0xC0) == 0x80) --cut;
          name.resize(cut);
          it->second = (outputs.path() / ("output" + std::to_string(files.size()) + "_" + name)).string();
        }
        c.name = it->second;
      }

      const Before before_it = before(c, session);
      std::variant<nlohmann::ordered_json, std::string> result;
      try {
        result = shell.execute(c);
      } catch (const std::exception& e) {
        fail("execute threw", e.what());
      }
      ++executed;
      watches_run += c.kind == Kind::Watch;

      if (auto* error = std::get_if<std::string>(&result)) {
        if (!may_fail(c, session, before_it))
          fail("a command that cannot fail failed", std::to_string(c.line) + ": " + *error);
      } else {
        check_answer(c, std::get<nlohmann::ordered_json>(result), session, before_it, simulation_at);
      }

      // However the current step was reached, its simulation is the same.
      const uint64_t simulation = session.hash().simulation;
      const auto [seen, first] = simulation_at.try_emplace(session.current(), simulation);
      if (!first && seen->second != simulation)
        fail("a step's simulation hash differs with the way it was reached", std::to_string(session.current()));
    }
  }
  if (!std::filesystem::is_empty(outputs.path())) outputs.clear();
  return 0;
}
