// Why: the causal history of a value, and of a match (docs/design.md §7b). An event is a module's
// program running at a step, or a write from outside the programs at the start of one (an action,
// an intervention, a scenario's [[event]]). The causes of a program's event (m, w): the outside
// writes on m at w, m's own event at w - 1, the messages m read at w (each caused by its sender's
// event at the step it was sent) and N(m, w) where it differs from N(m, w - 1) (caused by the
// program that asked for a move or a pivot, or else by the World: a root). The cone to depth D
// is every event at step w - D or later from which a chain of causes leads to the value's origin;
// the narrow cone keeps the events where a variable changed or a message was new, linked through
// the dropped ones. Everything is a function of the history: the same on any thread count, after
// any seek.
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "sim/causal_history.h"
#include "watch/frame.h"

namespace dw::sim {

class Session;
struct Control;

// A value whose history is asked for: variable `column` of module m at step t, and its origin w
// (origin_step).
struct ValueAsked {
  ModuleId module = 0;
  int column = 0;
  int64_t t = 0;
  int64_t origin = 0;
};

struct ConeEvent {
  // The program, or OutsideWrite::By as 1 + its value; Initial: an origin at step 0 that no one
  // wrote (the scenario's initial value).
  enum class Writer : uint8_t { Program, Action, Intervention, Event, Initial };
  ModuleId module = 0;
  int64_t step = 0;
  Writer writer = Writer::Program;
  bool removes = false;  // an outside write that takes the module out
  // An action's watchpoint (its position) and match (step and group; -1 and none when unknown).
  uint32_t watch = 0;
  int64_t match_t = -1;
  std::vector<ModuleId> match_group;
  struct Change {
    int column = 0;
    int64_t before = 0, after = 0;
  };
  std::vector<Change> changed;
  std::vector<size_t> causes;  // indices of the cone's events
  bool origin = false;         // the origin of a value asked for
  bool group = false;          // a module of the match's group
};

struct ConeMessage {
  ModuleId from = 0, to = 0;
  int64_t sent = 0, read = 0;
  std::vector<int64_t> words;
  bool is_new = true;  // not the words the sender sent the receiver one step earlier
};

struct NeighbourChange {
  enum class Reason : uint8_t { Move, Pivot, Removal, World };
  ModuleId module = 0;
  int64_t step = 0;
  std::vector<ModuleId> added, removed;
  Reason reason = Reason::World;
  ModuleId by = 0;  // the module that moved or was removed
};

struct ConeValue {
  ValueAsked asked;
  int64_t value = 0;
  ConeEvent::Writer writer = ConeEvent::Writer::Program;  // its origin's
  size_t event = 0;                                       // its origin event
};

struct Cone {
  std::vector<ConeValue> values;
  int depth = 3;
  bool narrow = false;
  std::vector<ConeEvent> events;  // by step, then module, then writer
  std::vector<ConeMessage> messages;
  std::vector<NeighbourChange> neighbours;
};

// The cone of each value (their union), to depth `depth`, over a history that holds steps
// origin - depth - 1 through the latest origin (clipped at step 0).
Cone cone_of(const CausalHistory& history, std::span<const ValueAsked> values, int depth, bool narrow);

// The first step a cone of these values needs recorded.
int64_t window_start(std::span<const ValueAsked> values, int depth);

// The cone of variable `column` of module m at step t (0 <= t <= latest) in the session's
// history; nothing when cancelled or when the session keeps no history.
std::optional<Cone> why_value(Session& session, ModuleId m, int column, int64_t t, int depth, bool narrow,
                              const Control& control);
// The cone of a match of watchpoint w at step t with this group (its slots' modules): the union
// of the cones of the values its watchpoint reads (each slot's variables at the match's step plus
// the read's offset, and each variable its aggregates read of their elements: N(m), within(m, h),
// all, component(m: c) as they stood then), its group's events marked.
std::optional<Cone> why_match(Session& session, uint32_t w, int64_t t, std::span<const ModuleId> group, int depth,
                              bool narrow, const Control& control);

// The session's `record FILE --messages`: steps 0..latest as a wptrace v1 trace whose header lists
// the interventions and watchpoints (Session::record's), each line with what its module read at its
// step ("recv", as `run --record-messages` writes it); the cursor stays. An error message, or
// empty ("cancelled" when cancelled).
std::string record_with_messages(Session& session, std::ostream& out, const Control& control);

// The cone as JSON (docs/session.md, `why`): modules by their ids, variables and watchpoints by
// their names; `group` marks a match's group.
std::string cone_json(const Cone& cone, const watch::Universe& universe, std::span<const std::string> watch_names);

}  // namespace dw::sim
