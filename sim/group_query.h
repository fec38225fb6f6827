// Asking the history about given modules, as a time-travel debugger searches it (rr's
// reverse-continue to a watchpoint; docs/session.md, "find" and "eval"): the step before or after
// the current one at which a module's variable changed, and a condition in the watch language
// decided on a group at a step (the window's pinned expressions) or searched for back and on.
//
// A condition is a watchpoint's program whose slots the group fills in order, read as the
// centralized detector reads one binding (every slot's "now" at the step, docs/design.md §4): its
// terms, offsets, neighbor() tests and aggregates over N(m), within, all and component. The group
// need not be connected: this asks what holds of these modules, not whether they match.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "sim/model.h"
#include "watch/kleene.h"
#include "watch/program.h"
#include "watch/watchpoint.h"

namespace dw::sim {

class Session;
struct Control;

enum class SearchDirection { Back, On };

// Where a search stopped: the step found, none (searched the whole history that way), or cancelled.
struct Found {
  std::optional<int64_t> step;
  bool cancelled = false;
};

// The step nearest the current one, before it (Back) or after it up to the latest (On), at which
// variable `column` of module m changed: its value differs from the step before's, or m was absent
// the step before (step 0 counts as a change, as a value's origin does, §7b). Nothing found in a
// session that keeps no history.
Found find_change(Session& session, ModuleId m, int column, SearchDirection direction, const Control& control);

// Why `program` cannot be decided on a group of `group_size` modules; empty when it can: one module
// a slot, and no window kept by each module (those are worked out over the whole run and the
// history does not keep them; compile with watch::WindowKeeping::WrittenOut).
std::string why_undecidable(const watch::Program& program, size_t group_size);

// A condition written over a watchpoint's slot names (the window's pinned expressions:
// `a._priority > c._priority` on a match of `modules(a b c); ...`): `modules(a b c); expression`,
// compiled with its windows written out. Or the mistake, one line, its column counted in
// `expression`.
std::variant<watch::Watchpoint, std::string> condition_on_slots(const Model& model,
                                                                std::span<const std::string> slot_names,
                                                                std::string_view expression);

// The condition's truth on `group` at each step of [from, to] (0 <= from <= to <= latest): true,
// false, or unknown where it reads a step outside the history or an absent module. Nothing when
// cancelled. The cursor stays where it is.
std::optional<std::vector<watch::Truth>> truth_over(Session& session, const watch::Program& program,
                                                    std::span<const ModuleId> group, int64_t from, int64_t to,
                                                    const Control& control);

// The step nearest the current one, before it or after it up to the latest, at which the
// condition holds (is true) on `group`.
Found find_holding(Session& session, const watch::Program& program, std::span<const ModuleId> group,
                   SearchDirection direction, const Control& control);

}  // namespace dw::sim
