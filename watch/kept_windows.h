// Windows over one slot's own variables kept incrementally by each module (docs/design.md §4c,
// Costs): each module works out the window's value at a step from its own state at the step before
// and its condition at this step, in time independent of the window's length. A history holds the
// value and that state as columns after the program's variables (KeptWindow::column and the
// state columns after it), works them out as it records a frame, and a reading then reads the
// window as it reads a variable, at its own "now".
//
// Of a window at step s, j is kept when s − j ≥ d, d being the first step whose reads of the
// condition all fall at step 0 or later: the window covers steps lo = max(d, s − k) .. s, and is
// unknown before d. The state is the latest step (in [d, s]) at which the condition took each value
// the window's verdict turns on, so that a step leaving the window needs no work:
//   once[k](φ)          T if φ was T at a step ≥ lo, else U if it was U at one, else F
//   historically[k](φ)  F if φ was F at a step ≥ lo, else U if it was U at one, else T
//   times[k](φ)         U if φ was U at a step ≥ lo, else C(s) − C(lo − 1), C counting φ's Ts from d
//   since[k](φ, ψ)      T if ψ was T at p ≥ lo with φ T at every step after p (p the latest such:
//                       φ last not T at or before p); F if ψ was F at every step from max(lo, the
//                       last step φ was F); else U
//   since(φ, ψ)         S(s) = ψ(s) or (φ(s) and S(s − 1)), from S(d − 1) = F (one bit)
// Each equals its definition's `or`/`and`/count over the kept j (Kleene logic being distributive),
// as the random test of tests/watch/windows_test.cpp checks against the definition itself.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>

#include "watch/evaluator.h"
#include "watch/kleene.h"
#include "watch/program.h"

namespace dw::watch {

// A window's value and state at one step: column i of the window is `value[i]`, known or not.
struct KeptStep {
  std::array<int64_t, kMaxKeptColumns> value{};
  std::array<bool, kMaxKeptColumns> known{};
};

// The window's columns at step s of one module, given `read(column, step, out)` over the module's
// own history (its variables, and the window's columns at steps before s).
template <class Read>
KeptStep work_out_window(const Program& p, const KeptWindow& w, int64_t s, Read&& read, EvaluatorScratch& scratch) {
  KeptStep out;
  if (s < w.first_step) return out;  // no j kept: unknown
  struct Reader {
    Read& read;
    int64_t step;
    Value term(const ValueInstr& in) const {
      int64_t v = 0;
      return read(in.variable, step + in.offset, v) ? known_value(v) : Value{};
    }
    // The condition reads one module's own variables: no aggregate, no neighbour, no other slot.
    int open(const AggregateCode&) const { return -1; }
    Value bound(int, const ValueInstr&) const { return {}; }
    uint32_t bound_id(int) const { return 0; }
    Truth bound_adjacent(int, int, uint32_t) const { return kUnknown; }
    uint32_t slot_module(int) const { return 0; }
    Truth slot_adjacent(const ConditionTest&, uint32_t) const { return kUnknown; }
    int64_t now(int) const { return step; }
  } reader{read, s};
  Evaluator e(p, reader, scratch);
  const Truth phi = e.condition_program(w.phi);
  const bool first = s == w.first_step;

  if (w.k == 0) {  // unbounded since: one bit
    const Truth psi = e.condition_program(w.psi);
    int64_t before = 0;
    const Truth prior = first ? kFalse : read(w.column, s - 1, before) ? truth_of(before != 0) : kUnknown;
    const Truth t = kleene_or(psi, kleene_and(phi, prior));
    out.value[0] = t == kTrue;
    out.known[0] = t != kUnknown;
    return out;
  }

  // State column i at s − 1 (its start, at d: no step yet, or a count of 0); false when not held.
  constexpr int64_t kNever = -1;  // every step compared with is at least 0
  auto prior = [&](int i, int64_t start) {
    int64_t v = start;
    if (!first && !read(w.column + i, s - 1, v)) return false;
    out.value[static_cast<size_t>(i)] = v;
    out.known[static_cast<size_t>(i)] = true;
    return true;
  };
  auto latest = [&](int i, bool now) {
    if (now) out.value[static_cast<size_t>(i)] = s;
    return out.value[static_cast<size_t>(i)];
  };
  const int64_t lo = std::max<int64_t>(w.first_step, s - w.k);
  auto verdict = [&](Truth t) {
    out.value[0] = t == kTrue;
    out.known[0] = t != kUnknown;
  };
  switch (w.kind) {
    case WindowKind::Once: {
      if (!prior(1, kNever) || !prior(2, kNever)) return KeptStep{};
      const int64_t phi_true = latest(1, phi == kTrue), phi_unknown = latest(2, phi == kUnknown);
      verdict(phi_true >= lo ? kTrue : phi_unknown >= lo ? kUnknown : kFalse);
      return out;
    }
    case WindowKind::Historically: {
      if (!prior(1, kNever) || !prior(2, kNever)) return KeptStep{};
      const int64_t phi_false = latest(1, phi == kFalse), phi_unknown = latest(2, phi == kUnknown);
      verdict(phi_false >= lo ? kFalse : phi_unknown >= lo ? kUnknown : kTrue);
      return out;
    }
    case WindowKind::Times: {
      if (!prior(1, 0) || !prior(2, kNever)) return KeptStep{};
      out.value[1] += phi == kTrue;  // C(s): at most s + 1
      if (latest(2, phi == kUnknown) >= lo) return out;
      int64_t before = 0;  // C(lo − 1), 0 before d
      if (lo > w.first_step && !read(w.column + 1, lo - 1, before)) return out;
      out.value[0] = out.value[1] - before;
      out.known[0] = true;
      return out;
    }
    case WindowKind::Since: {
      if (!prior(1, kNever) || !prior(2, kNever) || !prior(3, kNever) || !prior(4, kNever)) return KeptStep{};
      const Truth psi = e.condition_program(w.psi);
      const int64_t psi_true = latest(1, psi == kTrue), psi_not_false = latest(2, psi != kFalse);
      const int64_t phi_not_true = latest(3, phi != kTrue), phi_false = latest(4, phi == kFalse);
      if (psi_true >= lo && phi_not_true <= psi_true) verdict(kTrue);
      else verdict(psi_not_false < std::max(lo, phi_false) ? kFalse : kUnknown);
      return out;
    }
  }
  return out;
}

}  // namespace dw::watch
