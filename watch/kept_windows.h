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
#include <vector>

#include "watch/evaluator.h"
#include "watch/kleene.h"
#include "watch/program.h"

namespace dw::watch {

// A kept window's columns around step s, as arrays over the modules a history holds: what working
// out step s reads (at s − 1, and times' count at s − k − 1) and writes (at s). A null array is a
// step the history does not hold: what would be read from it is unknown.
struct KeptColumns {
  std::array<const int64_t*, kMaxKeptColumns> before{};
  std::array<const uint8_t*, kMaxKeptColumns> before_known{};
  const int64_t* count_left = nullptr;  // times: C(s − k − 1)
  const uint8_t* count_left_known = nullptr;
  std::array<int64_t*, kMaxKeptColumns> now{};
  std::array<uint8_t*, kMaxKeptColumns> now_known{};
};

// Of condition `truth` at step s, for modules [0, n): its truths, one per module. A comparison of
// a variable with a constant (the commonest) is read a column at a time; any other condition is
// evaluated module by module, `read(m, variable, step, out)` reading module m's own history.
template <class Column, class Read>
void condition_truths(const Program& p, uint32_t truth, int64_t s, size_t n, Column&& column, Read&& read,
                      EvaluatorScratch& scratch, std::vector<Truth>& out) {
  out.resize(n);
  const std::vector<ExprOp>& ops = p.truths[truth];
  if (ops.size() == 1 && ops[0].kind == ExprOp::PushLeaf) {
    const ConditionTest& t = p.tests[ops[0].leaf];
    if (t.kind == ConditionTest::Kind::Compare && p.codes[t.lhs].size() == 1 && p.codes[t.rhs].size() == 1) {
      const ValueInstr& term = p.codes[t.lhs][0];
      const ValueInstr& constant = p.codes[t.rhs][0];
      if (term.op == ValueOp::Term && term.variable >= 0 && constant.op == ValueOp::Constant) {
        const int64_t* values = nullptr;
        const uint8_t* known = nullptr;
        if (!column(term.variable, s + term.offset, values, known)) {
          std::fill(out.begin(), out.end(), kUnknown);
          return;
        }
        for (size_t m = 0; m < n; ++m)
          out[m] = known[m] ? compare_values(t.op, known_value(values[m]), known_value(constant.constant)) : kUnknown;
        return;
      }
    }
  }
  for (size_t m = 0; m < n; ++m) {
    struct Reader {
      Read& read;
      size_t module;
      int64_t step;
      Value term(const ValueInstr& in) const {
        int64_t v = 0;
        return read(module, in.variable, step + in.offset, v) ? known_value(v) : Value{};
      }
      // The condition reads one module's own variables: no aggregate, no neighbour, no other slot.
      int open(const AggregateCode&) const { return -1; }
      Value bound(int, const ValueInstr&) const { return {}; }
      uint32_t bound_id(int) const { return 0; }
      Truth bound_adjacent(int, int, uint32_t) const { return kUnknown; }
      uint32_t slot_module(int) const { return 0; }
      Truth slot_adjacent(const ConditionTest&, uint32_t) const { return kUnknown; }
      int64_t now(int) const { return step; }
      int expand(int) const { return 0; }
      int keep(const std::vector<uint8_t>&) const { return 0; }
    } reader{read, m, s};
    out[m] = Evaluator(p, reader, scratch).condition_program(truth);
  }
}

// Works out the window's columns at step s for modules [0, n), from its conditions' truths at s
// (`psi` read by a since only) and its columns before.
inline void advance_window(const KeptWindow& w, int64_t s, const Truth* phi, const Truth* psi, const KeptColumns& c,
                           size_t n) {
  const int columns = w.columns();
  auto unknown = [&](size_t m) {
    for (int i = 0; i < columns; ++i) {
      c.now[size_t(i)][m] = 0;
      c.now_known[size_t(i)][m] = 0;
    }
  };
  if (s < w.first_step) {  // no j kept: unknown
    for (size_t m = 0; m < n; ++m) unknown(m);
    return;
  }
  const bool first = s == w.first_step;
  auto verdict = [&](size_t m, Truth t) {
    c.now[0][m] = t == kTrue;
    c.now_known[0][m] = t != kUnknown;
  };
  if (w.k == 0) {  // unbounded since: one bit
    for (size_t m = 0; m < n; ++m) {
      Truth prior = kFalse;
      if (!first) prior = c.before[0] && c.before_known[0][m] ? truth_of(c.before[0][m] != 0) : kUnknown;
      verdict(m, kleene_or(psi[m], kleene_and(phi[m], prior)));
    }
    return;
  }
  constexpr int64_t kNever = -1;  // no step yet: every step compared with is at least 0
  const int64_t lo = std::max<int64_t>(w.first_step, s - w.k);
  for (size_t m = 0; m < n; ++m) {
    // The state at s − 1 (at d: no step yet, and a count of 0), then at s.
    std::array<int64_t, kMaxKeptColumns> st{};
    bool held = true;
    for (int i = 1; i < columns; ++i) {
      const bool count = w.kind == WindowKind::Times && i == 1;
      if (first) st[size_t(i)] = count ? 0 : kNever;
      else if (c.before[size_t(i)] && c.before_known[size_t(i)][m]) st[size_t(i)] = c.before[size_t(i)][m];
      else held = false;
    }
    if (!held) {
      unknown(m);
      continue;
    }
    auto latest = [&](int i, bool now) {
      if (now) st[size_t(i)] = s;
      return st[size_t(i)];
    };
    switch (w.kind) {
      case WindowKind::Once: {
        const int64_t phi_true = latest(1, phi[m] == kTrue), phi_unknown = latest(2, phi[m] == kUnknown);
        verdict(m, phi_true >= lo ? kTrue : phi_unknown >= lo ? kUnknown : kFalse);
        break;
      }
      case WindowKind::Historically: {
        const int64_t phi_false = latest(1, phi[m] == kFalse), phi_unknown = latest(2, phi[m] == kUnknown);
        verdict(m, phi_false >= lo ? kFalse : phi_unknown >= lo ? kUnknown : kTrue);
        break;
      }
      case WindowKind::Times: {
        st[1] += phi[m] == kTrue;  // C(s): at most s + 1
        const bool any_unknown = latest(2, phi[m] == kUnknown) >= lo;
        const bool left = lo > w.first_step;  // C(lo − 1) = C(s − k − 1); 0 before d
        const bool known = !any_unknown && (!left || (c.count_left && c.count_left_known[m]));
        c.now[0][m] = known ? st[1] - (left ? c.count_left[m] : 0) : 0;
        c.now_known[0][m] = known;
        break;
      }
      case WindowKind::Since: {
        const int64_t psi_true = latest(1, psi[m] == kTrue), psi_not_false = latest(2, psi[m] != kFalse);
        const int64_t phi_not_true = latest(3, phi[m] != kTrue), phi_false = latest(4, phi[m] == kFalse);
        if (psi_true >= lo && phi_not_true <= psi_true) verdict(m, kTrue);
        else verdict(m, psi_not_false < std::max(lo, phi_false) ? kFalse : kUnknown);
        break;
      }
    }
    for (int i = 1; i < columns; ++i) {
      c.now[size_t(i)][m] = st[size_t(i)];
      c.now_known[size_t(i)][m] = 1;
    }
  }
}

}  // namespace dw::watch
