// What `why` (docs/design.md §7b) reads of the history: over a window of steps, every module's
// variables, presence and neighbours, the messages each one read (sender, step sent, words), the
// writes made from outside the programs at the start of each step (a watchpoint's action, an
// intervention, a scenario's [[event]]) and the modules making a lattice move or a pivot. A live
// run keeps none of it: a session records a window when asked, by re-simulating it from its
// keyframes (record_window); a trace recorded with messages gives the same (sim/trace.h).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "sim/neighbor_graph.h"

namespace dw::sim {

class Session;
struct Control;

// A write from outside the programs, at the start of its step before the programs run.
struct OutsideWrite {
  enum class By : uint8_t { Action, Intervention, Event };
  By by = By::Intervention;
  ModuleId module = 0;
  int column = -1;  // the variable set; -1 when it sets none (a removal, a push)
  int64_t value = 0;
  bool remove = false;
  // An action's watchpoint (its position in the session) and the match whose action it is: its
  // step and group (empty when the session no longer lists it).
  uint32_t watch = 0;
  int64_t match_t = -1;
  std::vector<ModuleId> match_group;
};

// A message as `why` follows it: read at the record's step by `to`, sent by `from` at `sent`
// (the step before, for the runtime's messages); its words in the record's `words`.
struct ReadMessage {
  ModuleId from = 0, to = 0;
  int64_t sent = 0;
  uint32_t first = 0;
  uint32_t size = 0;
};

// A module making a lattice move or a pivot as the neighbours of a step were measured: its
// program asked for it at step start - 1.
struct MovingModule {
  ModuleId module = 0;
  int64_t start = 0;
  bool pivot = false;
};

// One step s of the window.
struct StepRecord {
  int64_t step = 0;
  std::vector<int64_t> values;                 // after the step: [module * variables + column]
  std::vector<uint8_t> present;                // at the step
  std::shared_ptr<const NeighborGraph> graph;  // N(·, s)
  std::vector<ReadMessage> read;               // read at s, grouped by receiver in module order
  std::vector<uint32_t> read_begin;            // [module_count + 1] into `read`; empty when none
  std::vector<int64_t> words;
  std::vector<OutsideWrite> outside;  // applied at the start of s, in their order
  std::vector<MovingModule> moving;   // as N(·, s) was measured, by module

  std::span<const ReadMessage> read_by(ModuleId m) const {
    if (read_begin.empty()) return {};
    return {read.data() + read_begin[m], read.data() + read_begin[m + 1]};
  }
  std::span<const int64_t> words_of(const ReadMessage& m) const { return {words.data() + m.first, m.size}; }
  const MovingModule* mover(ModuleId m) const;
  // Fills read_begin from `read`, which must be in receiver order.
  void index_reads(uint32_t modules);
};

// Steps first..last() of a run, and the values of step first - 1 (the initial values when first
// is 0).
struct CausalHistory {
  uint32_t modules = 0, variables = 0;
  int64_t first = 0;
  std::vector<int64_t> before;
  std::vector<StepRecord> steps;

  int64_t last() const { return first + static_cast<int64_t>(steps.size()) - 1; }
  bool holds(int64_t s) const { return s >= first && s <= last(); }
  const StepRecord& at(int64_t s) const { return steps[static_cast<size_t>(s - first)]; }
  // Module m's variable `column` after step s (first - 1 <= s <= last()).
  int64_t value(int64_t s, ModuleId m, int column) const {
    const std::vector<int64_t>& v = s < first ? before : at(s).values;
    return v[size_t{m} * variables + static_cast<size_t>(column)];
  }
  // The value a program at step s read before it ran: step s - 1's, with the outside writes of s.
  int64_t value_read(int64_t s, ModuleId m, int column) const;
  // Present at step s; a step before the window counts as present.
  bool present(int64_t s, ModuleId m) const { return !holds(s) || at(s).present[m] != 0; }
};

// The origin of a value (docs/design.md §7b): the latest step w <= t at which variable `column`
// of module m differs from its value at w - 1 (or m was absent at w - 1, or w = 0). Found in the
// session's history (re-simulating module m's values backwards from t, in growing windows);
// nothing when cancelled.
std::optional<int64_t> origin_step(Session& session, ModuleId m, int column, int64_t t, const Control& control);

// What a window records: everything `why` follows, or only the states a watchpoint's condition
// reads (values, presence, neighbours) -- the messages are most of a step's record.
enum class Recording : uint8_t { Causes, States };

// Records steps [first, last] of the session's history (0 <= first <= last <= latest), moving
// its cursor there and back: nothing when cancelled, or when the session keeps no history.
std::optional<CausalHistory> record_window(Session& session, int64_t first, int64_t last, const Control& control,
                                           Recording recording = Recording::Causes);

}  // namespace dw::sim
