// Windows in time written out over their shifts (docs/design.md §4c), so that every reading evaluates
// them as it evaluates any other term: `once[k](φ)` becomes the `or`, over j = 0..k, of "j is kept
// and φ(−j)", where φ(−j) is a copy of φ with every offset lowered by j, and "j is kept" compares
// the step of φ's earliest read (a `Step` node: a slot's "now" plus an offset, known before step 0
// too) with j. A window with no j kept is unknown. So each reading, with its own "now" per slot,
// clips each window at step 0 exactly as §4c says, with no code of its own.
//
// The cost of a bounded window is the definition's: a window of length k is k + 1 copies of its
// condition, evaluated at every step, and the history keeps the k steps they read (§4c's
// incremental rings of bits are not built yet). An unbounded since is one bit a module keeps per
// step (a SinceBit node, watch/since_bits.h), whatever the past.
#pragma once

#include <vector>

#include "watch/ast.h"
#include "watch/diagnostic.h"

namespace dw::watch {

// Most nodes the written-out windows may add (nested windows multiply): past it, an error.
constexpr size_t kMaxEvaluatedNodes = 400'000;

// Sets ast.evaluated (and each set action's `evaluated`) when the watchpoint has a window; leaves
// them unset when it has none. Requires an Ast that parsed without diagnostics. Returns the
// errors that stop it from being evaluated (too large once written out).
std::vector<Diagnostic> write_out_windows(Ast& ast);

// Of an unbounded since: the first step whose reads of φ and ψ all fall at step 0 or later, and the
// largest offset they read (at least 0).
void since_steps(const Ast& ast, NodeIndex since, int& first_step, int& ahead);

// How far back `window` looks from its step: its length, plus the deepest 'last' inside it,
// nested windows added (docs/design.md §4c; counted toward the offset limit of §3).
int64_t window_reach(const Ast& ast, NodeIndex window);

}  // namespace dw::watch
