// What both detectors share: options, statistics, the match sink and the driving interface.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "watch/frame.h"
#include "watch/value.h"

namespace dw::watch {

// The paper's §IV optimizations. Each can be switched off; results never change (docs/design.md §4).
struct Optimizations {
  bool early_termination = true;  // drop a PatternMatcher whose expression is already false
  bool neighbor_culling = true;   // spread only to modules that can satisfy neighbor() terms
  bool temporal_spans = true;     // keep each variable's history for exactly its span
};

// The names a setting accepts, as a message offers them: "a", "b" or "c" (`values` in order).
template <typename Value, size_t N, typename Name>
std::string one_of(const Value (&values)[N], Name name) {
  std::string s;
  for (size_t i = 0; i < N; ++i)
    s += std::string(i == 0 ? "" : i + 1 == N ? " or " : ", ") + "\"" + std::string(name(values[i])) + "\"";
  return s;
}

enum class Algorithm { Centralized, Distributed };
inline constexpr Algorithm kAlgorithms[] = {Algorithm::Centralized, Algorithm::Distributed};
const char* algorithm_name(Algorithm a);
std::optional<Algorithm> parse_algorithm(std::string_view name);
inline std::string algorithm_names() { return one_of(kAlgorithms, algorithm_name); }

// Which connected groups match (docs/design.md §4a), over the neighbour graph at the match's step:
// Chain, a path in slot order; Ordered, each slot a neighbour of an earlier one (the paper's
// Alg. 1); Any, every connected group in every slot assignment.
enum class GroupShape : uint8_t { Chain, Ordered, Any };
inline constexpr GroupShape kShapes[] = {GroupShape::Chain, GroupShape::Ordered, GroupShape::Any};
const char* shape_name(GroupShape s);
std::optional<GroupShape> parse_shape(std::string_view name);
inline std::string shape_names() { return one_of(kShapes, shape_name); }

// Which states the distributed algorithm compares (docs/design.md §4a): Consistent, each slot at its own
// fill step (the paper's Alg. 2); Simultaneous, every slot at the PatternMatcher's start step.
enum class States : uint8_t { Consistent, Simultaneous };
inline constexpr States kStates[] = {States::Consistent, States::Simultaneous};
const char* states_name(States s);
std::optional<States> parse_states(std::string_view name);
inline std::string states_names() { return one_of(kStates, states_name); }

struct DetectorOptions {
  Optimizations optimizations;
  // Most PatternMatchers alive in one step; past it the detector stops. 0 means no limit.
  uint64_t live_budget = 0;
  std::optional<GroupShape> shape;  // unset: the algorithm's own (see group_shape)
  std::optional<States> states;     // unset: consistent (distributed); the centralized is simultaneous
};

// The shape a detector finds: the option, or the paper's (ordered centralized, chain distributed).
GroupShape group_shape(Algorithm algorithm, const DetectorOptions& options);
// Whether the distributed algorithm runs in simultaneous-state mode.
bool simultaneous(Algorithm algorithm, const DetectorOptions& options);
// Why an algorithm cannot run with these options, or "" when it can.
std::string unsupported(Algorithm algorithm, const DetectorOptions& options);

// Hops a simultaneous-state PatternMatcher of k slots takes at most before it is decided (L in
// docs/design.md §4a): k - 1 for chains, where each slot is one hop from the one before; k(k - 1)/2 for
// ordered and any groups, where reaching slot i + 1 may mean walking back through the i slots
// filled so far (at most i - 1 hops over their tree) and one hop on.
int64_t hop_latency(GroupShape shape, int slots);

class Program;
// Steps between a frame and the watch step it completes (docs/design.md §7, "decided steps"): E+ for the
// centralized detector, E+ + k - 1 for the distributed one, whose PatternMatchers take a step
// per slot, E+ + L in simultaneous-state mode. The one definition every detector, the runtime
// and the session use.
int64_t lag(const Program& program, Algorithm algorithm, const DetectorOptions& options);

// Statistics of one detector step (the paper's Fig. 7 series is `live_by_filled`).
struct StepStats {
  int64_t step = 0;                      // the detector step (its "now"), not the frame's
  std::vector<uint64_t> live_by_filled;  // [slots filled] -> PatternMatchers alive with that many
  uint64_t live = 0;
  uint64_t created = 0;
  uint64_t messages = 0;  // distributed: PatternMatchers sent to a neighbour
  uint64_t bytes = 0;     // distributed: their size
  uint64_t lost = 0;      // simultaneous states: PatternMatchers dropped by a link gone before their hop
  // Distributed: the messages that bring each module its neighbours' values for an aggregate
  // (docs/design.md §7's hop), one per present module and neighbour a step.
  uint64_t value_messages = 0;
  uint64_t matches = 0;
  double seconds = 0;
};

struct DetectorStats {
  // The per-step series, for the first kMaxSteps steps; the totals below count every step.
  static constexpr size_t kMaxSteps = 1'000'000;
  size_t max_steps = kMaxSteps;  // a live run keeps its own series and sets 0
  std::vector<StepStats> steps;
  StepStats last;  // the most recent step
  bool steps_truncated = false;
  std::vector<uint64_t> created_by_filled;  // over the run
  uint64_t created = 0, messages = 0, bytes = 0, matches = 0, lost = 0, value_messages = 0;
  uint64_t observed_steps = 0;  // detector steps run (added)
  uint64_t peak_live = 0;
  uint64_t history_values = 0;  // values held in history at the end (all modules)
  double seconds = 0;
  bool stopped = false;  // the live budget was exceeded
  std::string stop_reason;

  void add(const StepStats& s);
};

// Receives the matches of one watch step `t`: `slots` holds count * slot_count module ids,
// each match's ids in slot order; `actions`, of a watchpoint with actions (docs/design.md §4b), count *
// action_count values, each match's in action order (a `remove`'s is 0), and is empty otherwise.
// Called at most once per t, in increasing t, and only for a step with a match: a zero-slot
// watchpoint's (docs/design.md §4c) call, with no ids, is its step's one match. How many matches a
// call holds is match_rows, never ids / slot_count.
using MatchSink = std::function<void(int64_t t, std::span<const ModuleId> slots, std::span<const Value> actions)>;

// The matches (rows) in `ids` module ids of a watchpoint of `slot_count` slots, as a sink or a
// step's match list holds them: a zero-slot watchpoint's match is a row with no ids, one a step.
inline size_t match_rows(size_t ids, size_t slot_count) { return slot_count == 0 ? 1 : ids / slot_count; }

// For each program variable, the frame column that carries it, or -1 when frames never do.
class Program;
std::vector<int> variable_columns(const Program& program, const Universe& universe);

class Detector {
 public:
  Detector(const Universe& universe, MatchSink sink);
  virtual ~Detector() = default;
  // Frames arrive in step order 0, 1, 2, ... A watch step t is decided once frame t + lag() has
  // been observed; its matches go to the sink then.
  virtual void observe(const Frame& frame) = 0;
  // The input has ended: decide every watch step the frames observed can decide, as far as the
  // last frame allows (a simultaneous-state detector drains its PatternMatchers in flight).
  virtual void finish() {}
  // Steps between a frame and the watch step it completes: E+ (centralized), E+ + k - 1 (distributed).
  virtual int64_t lag() const = 0;
  virtual Algorithm algorithm() const = 0;
  // A copy of everything the detector holds, for snapshots; it sends matches to the same sink.
  virtual std::unique_ptr<Detector> clone() const = 0;
  // Heap bytes the detector's state holds, estimated (for a session's history budget).
  virtual size_t bytes() const = 0;
  void set_sink(MatchSink sink) { sink_ = std::move(sink); }
  DetectorStats& stats() { return stats_; }
  const DetectorStats& stats() const { return stats_; }
  bool stopped() const { return stats_.stopped; }

 protected:
  // Hands the matches of watch step t, in dense module indices, to the sink as module ids, with
  // their actions' values.
  void emit(int64_t t, std::span<const uint32_t> dense, std::span<const Value> actions = {});
  // Hands a zero-slot watchpoint's match of watch step t (a row with no module) to the sink.
  void emit_row(int64_t t) { sink_(t, {}, {}); }

  const Universe& universe_;
  DetectorStats stats_;

 private:
  MatchSink sink_;
  bool dense_ids_are_ids_ = true;  // module ids 0..M-1 in order: matches need no translation
  std::vector<ModuleId> ids_;
};

}  // namespace dw::watch
