// Windows in time written out over their shifts (docs/design.md §4c), so that every reading evaluates
// them as it evaluates any other term: `once[k](φ)` becomes the `or`, over j = 0..k, of "j is kept
// and φ(−j)", where φ(−j) is a copy of φ with every offset lowered by j, and "j is kept" compares
// the step of φ's earliest read (a `Step` node: a slot's "now" plus an offset, known before step 0
// too) with j. A window with no j kept is unknown. So each reading, with its own "now" per slot,
// clips each window at step 0 exactly as §4c says, with no code of its own.
//
// A window over one slot's own variables is not written out: each module keeps it incrementally
// (a KeptWindow node, read as a column: watch/kept_windows.h), at a cost per step independent of
// its length, as §4c's Costs ask. The rest (windows reading neighbours, aggregates, id() or other
// slots) cost the definition's: k + 1 copies of the condition, evaluated at every step.
#pragma once

#include <vector>

#include "watch/ast.h"
#include "watch/diagnostic.h"

namespace dw::watch {

// Most nodes the written-out windows may add (nested windows multiply): past it, an error.
constexpr size_t kMaxEvaluatedNodes = 400'000;

// Which windows over one slot's own variables stay kept by each module: all that can (a watch over
// a run), or none (a condition asked of a group at a few steps of the history, sim/group_query.h,
// where no module has kept anything: every window is written out).
enum class WindowKeeping : uint8_t { ByModule, WrittenOut };

// Sets ast.evaluated (and each set action's `evaluated`) when the watchpoint has a window; leaves
// them unset when it has none. Requires an Ast that parsed without diagnostics. Returns the
// errors that stop it from being evaluated (too large once written out).
std::vector<Diagnostic> write_out_windows(Ast& ast, WindowKeeping keeping = WindowKeeping::ByModule);

// Whether `window` (as written) is kept by each module incrementally (watch/kept_windows.h): its
// conditions read one slot's own variables (no neighbor(), aggregate, id() or bound name), or
// nothing. An unbounded since always is (the parser makes sure).
bool kept_by_module(const Ast& ast, NodeIndex window);

// Of a kept window: the first step whose reads of its conditions all fall at step 0 or later, the
// largest offset they read (at least 0), and, for conditions that read only ahead, how far they are
// lifted back (their earliest read) so that they start at step 0 — the column is read that much
// further ahead.
struct KeptSteps {
  int first_step = 0, ahead = 0, lift = 0;
};
KeptSteps kept_steps(const Ast& ast, NodeIndex window);

// How far back `window` looks from its step: its length, plus the deepest 'last' inside it,
// nested windows added (docs/design.md §4c; counted toward the offset limit of §3).
int64_t window_reach(const Ast& ast, NodeIndex window);

}  // namespace dw::watch
