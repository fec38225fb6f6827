// One description of a watchpoint (docs/design.md §3, §5): its name, its text, how it is read
// (algorithm, group shape, states, budget, optimizations) and what its matches do (its action).
// Every place that takes or gives a watchpoint's settings goes through it: the session's `watch`
// words, the command line's flags, a trace's header (JSON), a scenario's [[watch]] (TOML), the
// shell's answers and the Python package. Compiled, it is a HostedWatchpoint, what a run hosts.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "watch/detector.h"
#include "watch/watchpoint.h"

namespace dw::sim {

// Most PatternMatchers a watchpoint may keep alive in one step unless it says otherwise: past it
// the watchpoint stops (watch::DetectorOptions::live_budget).
inline constexpr uint64_t kDefaultMatchBudget = 20'000'000;
// Most PatternMatchers all of a run's watchpoints together may keep alive in one step unless the
// run says otherwise (watch::RunBudget, --max-live-all): 24 watchpoints each under its own budget
// would otherwise hold 24 times one's memory.
inline constexpr uint64_t kDefaultRunBudget = 50'000'000;

// What happens when a watchpoint matches.
enum class MatchAction {
  Pause,  // the run stops at the match's step and reports the group
  Log,    // the match is kept (and written with --matches); the run goes on
  Count,  // only counted
};
inline constexpr MatchAction kActions[] = {MatchAction::Pause, MatchAction::Log, MatchAction::Count};
std::string_view action_name(MatchAction a);
std::optional<MatchAction> parse_action(std::string_view name);
inline std::string action_names() { return watch::one_of(kActions, action_name); }
// Whether a watchpoint lists its matches, each group with its actions' values: a `count` one keeps
// only their number (of each step), which is all the match log, the session and the runtime keep.
inline bool lists_matches(MatchAction a) { return a != MatchAction::Count; }

// A compiled watchpoint with its reading and action: what a run hosts.
struct HostedWatchpoint {
  watch::Watchpoint watchpoint;
  watch::Algorithm algorithm = watch::Algorithm::Distributed;
  MatchAction action = MatchAction::Log;
  watch::DetectorOptions options;

  // Steps between a state and the watch step it completes (watch::lag).
  int64_t lag() const { return watch::lag(watchpoint.program, algorithm, options); }
  // The paper's distributed algorithm runs on the modules, as agents the runtime steps with
  // them; every other reading is a detector observing the run's frames, and so is a zero-slot
  // watchpoint in every reading (no module to run on: docs/design.md §4c, watch/ensemble_detector.h).
  bool runs_on_agents() const {
    return algorithm == watch::Algorithm::Distributed && !watch::simultaneous(algorithm, options) &&
           watchpoint.program.slot_count() > 0;
  }
};

// The watchpoints a run hosts, in the order its states hold them (State::watches), each where its
// owner keeps it: a list (a scenario's, a test's) or a session's slots. A view: its owner makes
// the runtime again when they change.
class HostedWatches {
 public:
  HostedWatches() = default;
  // Implicit: a list is the watch set it holds.
  HostedWatches(std::span<const HostedWatchpoint> list) {
    for (const HostedWatchpoint& h : list) each_.push_back(&h);
  }
  HostedWatches(const std::vector<HostedWatchpoint>& list) : HostedWatches(std::span(list)) {}
  explicit HostedWatches(std::vector<const HostedWatchpoint*> each) : each_(std::move(each)) {}

  size_t size() const { return each_.size(); }
  bool empty() const { return each_.empty(); }
  const HostedWatchpoint& operator[](size_t w) const { return *each_[w]; }
  struct Iterator {
    const HostedWatchpoint* const* at;
    const HostedWatchpoint& operator*() const { return **at; }
    Iterator& operator++() {
      ++at;
      return *this;
    }
    bool operator==(const Iterator&) const = default;
  };
  Iterator begin() const { return {each_.data()}; }
  Iterator end() const { return {each_.data() + each_.size()}; }

  // Most PatternMatchers all of them together keep alive in a step (watch::RunBudget); 0: no limit.
  uint64_t run_budget = kDefaultRunBudget;

 private:
  std::vector<const HostedWatchpoint*> each_;
};

struct WatchSpec {
  std::string name;
  std::string text;  // modules(...); ...
  watch::Algorithm algorithm = watch::Algorithm::Distributed;
  // The shape and states (unset: the algorithm's own), the budget and the optimizations.
  watch::DetectorOptions options{.live_budget = kDefaultMatchBudget};
  MatchAction action = MatchAction::Log;

  // The reading as every output names it: the shape it finds (the algorithm's own when none is
  // given), and the states a distributed one compares (consistent when none is given).
  const char* algorithm_name() const { return watch::algorithm_name(algorithm); }
  const char* shape_name() const { return watch::shape_name(watch::group_shape(algorithm, options)); }
  const char* states_name() const { return watch::states_name(options.states.value_or(watch::States::Consistent)); }
  bool distributed() const { return algorithm == watch::Algorithm::Distributed; }
  // The session's `watch` words that give this reading and action: "distributed chain consistent
  // log" (the states only of a distributed one).
  std::string words() const;
};

// The parts of a reading a word names, in the order the session's `watch` says them.
enum class WatchWord { Algorithm, Action, Shape, States };
// "algorithm", "action", "shape", "states": the key a scenario's [[watch]] and a trace give it by.
const char* word_key(WatchWord part);
// The words a part takes, as a message offers them: "centralized" or "distributed".
std::string word_choices(WatchWord part);
// Reads one word into `spec`: an algorithm's, a shape's, a states' or an action's name sets that
// part (only a word of `only`, when given). Which part it set; nothing, `spec` unchanged, when
// the word names none. The session's `watch` words, the command line's flags, a trace's strings
// and a scenario's all go through here.
std::optional<WatchWord> read_word(WatchSpec& spec, std::string_view word, std::optional<WatchWord> only = {});
// A second watchpoint of one name in a list (a scenario, a trace, the command line): matches and
// logs name a watchpoint by it. The message, or empty.
std::string second_name_problem(std::string_view name, std::span<const WatchSpec> before);

// The spec of a hosted watchpoint: its text in normal form (watch::to_string).
WatchSpec spec_of(const HostedWatchpoint& hosted);
std::vector<WatchSpec> specs_of(const HostedWatches& hosted);
// The spec's text compiled elsewhere (`compiled`: a scenario file's compiles it in place), hosted
// with the spec's reading and action.
HostedWatchpoint hosted(const WatchSpec& spec, watch::Watchpoint compiled);
// Compiles the spec's text from `source` (its diagnostics name it and point into it; a text
// written inside a larger file keeps that file's positions) with its reading and action.
std::variant<HostedWatchpoint, watch::CompileError> compile(const WatchSpec& spec, watch::SourceText source);
// The same for a text that stands in `file` under the watchpoint's name: "FILE (watch NAME)".
std::variant<HostedWatchpoint, watch::CompileError> compile(const WatchSpec& spec, const std::string& file);
// Each compiled (see above); or the first one's compile errors, rendered.
std::variant<std::vector<HostedWatchpoint>, std::string> compile_all(std::span<const WatchSpec> specs,
                                                                     const std::string& file);

// As a trace's header lists a watchpoint, one JSON object:
//   {"name":"w","text":"modules(a); ...","algorithm":"distributed","shape":"chain",
//    "states":"consistent","action":"log"}
// (the budget and the optimizations are the replaying command's own).
nlohmann::ordered_json to_json(const WatchSpec& spec);
inline constexpr std::string_view kJsonKeys[] = {"name", "text", "algorithm", "shape", "states", "action"};
// And back, each key as the scenario loader checks a [[watch]]'s (its names, each reading and
// action one that runs, a name not among `before`'s): the spec, with the default budget and
// optimizations, or the first key at fault and why (`missing` when it is not a string).
struct SpecError {
  std::string key;
  std::string why;
  bool missing = false;
};
std::variant<WatchSpec, SpecError> spec_from_json(const nlohmann::json& object, std::span<const WatchSpec> before = {});

// As a scenario's [[watch]] table holds it (docs/design.md §5): its keys and values in order (a
// string, an integer or a boolean), every setting written out.
using TomlValue = std::variant<std::string, int64_t, bool>;
std::vector<std::pair<std::string_view, TomlValue>> toml_fields(const WatchSpec& spec);

}  // namespace dw::sim
