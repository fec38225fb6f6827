// A watchpoint compiled for evaluation over partial fills (paper §III, Fig. 4).
//
// The expression's leaves (comparisons and neighbor() terms) are each decided when the last slot
// they mention is filled: its `decide_slot`. Until then a leaf is Unknown. The expression itself
// is a postfix program over leaf truth values, evaluated in Kleene logic.
//
// A comparison of two plain operands (a variable, a constant) is decided inline; any other (docs/design.md
// §4b: arithmetic, aggregates over neighbours) compiles its two sides to postfix value code, run
// by watch/evaluator.h over whatever reads the detector's state.
//
// For the distributed detector, where a PatternMatcher travels and each module contributes only
// its own state, a term whose slot fills before the leaf's decide slot is carried in a *cell*, the
// neighbour set N(x) of a neighbor(x y) term with x filled before y is carried as a *set*, and an
// aggregate over a slot filled before is carried as a *table* of that module's neighbours.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "watch/analysis.h"
#include "watch/ast.h"
#include "watch/kleene.h"

namespace dw::watch {

// The variable index that stands for `id(m)` (docs/design.md §4c): the module's id, known when the
// module is present at that step. Read, carried and tabled as a variable is.
constexpr int16_t kIdVariable = -1;

// `slot.variable` at `offset` steps from the slot's "now".
struct TermRef {
  int16_t slot = 0;
  int16_t variable = 0;  // index into Program::variables
  int16_t offset = 0;
  int16_t cell = -1;  // >= 0: carried in this cell (distributed), the slot fills before decide_slot
};

// Calls fn with the comparison functor of `op` (std::less<int64_t>, ...): a loop written once
// inside fn is compiled once per operator, its body without a branch on the operator.
template <class Fn>
inline void with_compare(CompareOp op, Fn&& fn) {
  switch (op) {
    case CompareOp::Less: fn(std::less<int64_t>{}); break;
    case CompareOp::Greater: fn(std::greater<int64_t>{}); break;
    case CompareOp::Equal: fn(std::equal_to<int64_t>{}); break;
    case CompareOp::NotEqual: fn(std::not_equal_to<int64_t>{}); break;
    case CompareOp::GreaterEqual: fn(std::greater_equal<int64_t>{}); break;
    case CompareOp::LessEqual: fn(std::less_equal<int64_t>{}); break;
  }
}

// Whether `a op b` holds.
inline bool holds(CompareOp op, int64_t a, int64_t b) {
  switch (op) {
    case CompareOp::Less: return a < b;
    case CompareOp::Greater: return a > b;
    case CompareOp::Equal: return a == b;
    case CompareOp::NotEqual: return a != b;
    case CompareOp::GreaterEqual: return a >= b;
    case CompareOp::LessEqual: return a <= b;
  }
  return false;
}

// ---- value code (docs/design.md §4b) ------------------------------------------------------------------

enum class ValueOp : uint8_t {
  Constant,   // push `constant`
  Term,       // push slot.variable at offset (carried in `cell` when >= 0)
  Bound,      // push the aggregate's current neighbour's variable, `offset` from the aggregate's step
  Aggregate,  // push aggregate `index`
  Step,       // push the slot's "now" plus offset (docs/design.md §4c: where a window is clipped)
  Truth,      // push condition `index` (Program::truths) as 1, 0 or unknown
  Negate,
  Add,
  Subtract,
  Multiply,
  Divide,
  Remainder,
  Abs,
  Min,
  Max,
};

struct ValueInstr {
  ValueOp op = ValueOp::Constant;
  int16_t slot = 0, variable = 0, offset = 0;
  int16_t cell = -1;
  uint32_t index = 0;  // Aggregate, Truth
  int64_t constant = 0;
};

constexpr uint32_t kNoCode = UINT32_MAX;

// A test inside an aggregate's condition: a comparison of two value codes, or neighbor(x y) where
// x and y are slots or the bound name (its offset counts from the aggregate's step; a slot's from
// its own "now").
struct ConditionTest {
  enum class Kind : uint8_t { Compare, Neighbor };
  Kind kind = Kind::Compare;
  CompareOp op = CompareOp::Equal;
  uint32_t lhs = kNoCode, rhs = kNoCode;  // Compare: value codes
  int16_t x = 0, y = 0;                   // Neighbor: slots, or kBound
  int16_t offset = 0;
  int16_t set = -1;  // x a slot filled before the decide slot: N(x) is carried in this set
};
constexpr int16_t kBound = -1;

// Postfix Kleene logic over numbered tests: the watchpoint's expression over its leaves, and an
// aggregate's condition over its tests.
struct ExprOp {
  enum Kind : uint8_t { PushLeaf, Not, And, Or };
  Kind kind = PushLeaf;
  uint32_t leaf = 0;  // the leaf, or the test, to push
};

// Runs postfix logic: truth(i) gives what PushLeaf i pushes; `stack` holds the deepest it needs.
template <class TruthOf>
Truth run_logic(const std::vector<ExprOp>& ops, Truth* stack, TruthOf&& truth) {
  int sp = 0;
  for (const ExprOp& op : ops) {
    switch (op.kind) {
      case ExprOp::PushLeaf: stack[sp++] = truth(op.leaf); break;
      case ExprOp::Not: stack[sp - 1] = kleene_not(stack[sp - 1]); break;
      case ExprOp::And:
        --sp;
        stack[sp - 1] = kleene_and(stack[sp - 1], stack[sp]);
        break;
      case ExprOp::Or:
        --sp;
        stack[sp - 1] = kleene_or(stack[sp - 1], stack[sp]);
        break;
    }
  }
  return stack[0];
}

// `count(n in neighbors(a.last): cond)`, `sum/min/max(n in neighbors(a): expr)`.
struct AggregateCode {
  AggregateKind kind = AggregateKind::Count;
  int16_t slot = 0, offset = 0;       // ranges over N(slot's module, now + offset), present neighbours
  Domain domain = Domain::Neighbors;  // or within `hops` of it, or all modules present then (ast.h)
  int16_t hops = 1;
  std::vector<ExprOp> member_condition;  // component: what a candidate (the bound name) meets to join
  int member_depth = 0;
  uint32_t value = kNoCode;       // sum, min, max: the value of each neighbour
  std::vector<ExprOp> condition;  // count: over Program::tests, empty for none
  int condition_depth = 0;        // the truths its condition's evaluation needs
  // Distributed: >= 0 when its slot fills before the decide slot, and so the slot's module carries
  // its neighbours (ids, what the body reads of them) in this table.
  int16_t table = -1;
  // What the body reads of each neighbour: (variable, offset) values and neighbour sets at offsets.
  std::vector<TermRef> neighbor_reads;
  std::vector<int16_t> neighbor_sets;
};

// ---- leaves -----------------------------------------------------------------------------------

enum class LeafKind : uint8_t { Compare, Neighbor, Expression };

struct Leaf {
  LeafKind kind = LeafKind::Compare;
  CompareOp op = CompareOp::Equal;
  // Compare: a variable against a variable or a constant
  TermRef lhs;
  bool rhs_is_constant = false;
  TermRef rhs;
  int64_t constant = 0;
  // Expression: lhs_code op rhs_code
  uint32_t lhs_code = kNoCode, rhs_code = kNoCode;
  // neighbor(x y) at offset: y in N(x, now_x + offset)
  int16_t x = 0, y = 0, offset = 0;
  int16_t set = -1;  // >= 0: N(x) is carried in this set (x fills before y)
  int16_t decide_slot = 0;
  NodeIndex node = kNoNode;
};

struct CarriedCell {
  int16_t slot = 0, variable = 0, offset = 0;
};

// What a PatternMatcher carries as a variable-length record, appended as the slot that owns it
// fills: N(slot, now + offset) (a set), or a table of an aggregate over the slot's neighbours.
struct CarriedSet {
  int16_t slot = 0, offset = 0;
  int32_t aggregate = -1;  // >= 0: the table of this aggregate
};

// `then set a.v = expr` / `then remove a`, its value decided at the last slot.
// A window over one slot's own variables, kept incrementally by each module (watch/kept_windows.h):
// its value a step in column `column`, and the state it is worked out from in the columns after it
// (columns come after the program's variables).
constexpr int kMaxKeptColumns = 5;
struct KeptWindow {
  WindowKind kind = WindowKind::Since;
  int k = 0;  // its length; 0: an unbounded since
  int16_t slot = 0;
  uint32_t phi = 0, psi = 0;  // Program::truths (psi: a since's), offsets from the step worked out
  int first_step = 0;         // the first step whose reads of its conditions all fall at step 0 or later
  int ahead = 0;              // the largest offset they read: step s is worked out once s + ahead is
  int column = 0;             // its value's column
  int columns() const {
    if (k == 0) return 1;
    return kind == WindowKind::Since ? 5 : 3;
  }
};

struct ActionCode {
  Action::Kind kind = Action::Kind::Set;
  int16_t slot = 0;
  std::string variable;  // Set
  uint32_t value = kNoCode;
};

// What filling one slot involves.
struct SlotProgram {
  std::vector<uint16_t> cells;   // cells this slot's module writes
  std::vector<uint16_t> sets;    // neighbour sets and tables this slot's module writes
  std::vector<uint16_t> leaves;  // leaves decided when this slot fills
  // Of those, the ones the filling module decides from its own state alone (its own variables,
  // neighbours and constants): the same for every PatternMatcher it fills at a step, so an agent
  // decides them once per step.
  std::vector<uint16_t> own_leaves;
  std::vector<uint16_t> carried_leaves;  // the rest: they read cells, sets or earlier slots' ids
  std::vector<uint16_t> cull_leaves;     // neighbor(x this) leaves with x filled earlier: cull candidates
};

class Program {
 public:
  Program(const Ast& ast, const Analysis& analysis);

  int slot_count() const { return static_cast<int>(slot_names.size()); }
  // Steps a distributed reading waits behind a frame before it decides a step: E+, and the hop an
  // aggregate takes to learn its neighbours' values (docs/design.md §7).
  int agent_delay() const { return extent_plus + aggregate_hops; }

  // Evaluates the expression over leaf truth values; `stack` holds at least max_stack entries.
  Truth evaluate(const Truth* leaf_values, Truth* stack) const {
    if (shape == Shape::Conjunction) {
      // and over all leaves: may be true iff every leaf may be; may be false iff any may be.
      Truth all = 1, any = 0;
      const uint32_t n = leaf_count;  // a local: Truth is a char type and may alias it
      for (uint32_t i = 0; i < n; ++i) {
        all &= leaf_values[i];
        any |= leaf_values[i];
      }
      return static_cast<Truth>((all & 1) | (any & 2));
    }
    return run_logic(expr, stack, [&](uint32_t leaf) { return leaf_values[leaf]; });
  }

  std::vector<std::string> slot_names;
  std::vector<std::string> variables;
  std::vector<int> variable_min_offset;  // per variable
  int extent_plus = 0;                   // E+
  int aggregate_hops = 0;                // 0 to kMaxWithinHops (Analysis::aggregate_hops)
  int min_offset = 0;                    // <= 0
  int min_neighbor_offset = 0;           // <= 0; neighbour sets are read at [this, E+]
  std::vector<Leaf> leaves;
  uint32_t leaf_count = 0;  // leaves.size(), kept apart for the evaluation loop
  std::vector<ExprOp> expr;
  int max_stack = 1;
  // A plain conjunction of its leaves (the commonest watchpoint) evaluates without the stack.
  enum class Shape : uint8_t { General, Conjunction };
  Shape shape = Shape::General;
  std::vector<CarriedCell> cells;
  std::vector<CarriedSet> sets;  // ordered by slot: a PatternMatcher appends them as it fills
  std::vector<SlotProgram> slots;
  // Value code: each a postfix program over ValueInstr. Evaluating one needs at most
  // max_value_stack values and max_condition_stack truths of scratch.
  std::vector<std::vector<ValueInstr>> codes;
  std::vector<ConditionTest> tests;
  std::vector<AggregateCode> aggregates;
  // Conditions read as integers (ValueOp::Truth: a window written out, watch/windows.h), over tests,
  // with the truths each needs.
  std::vector<std::vector<ExprOp>> truths;
  std::vector<int> truth_depths;
  bool reads_id = false;  // some term is id(m): the readers need the modules' ids
  // Windows kept by each module, their columns after `variables`; variable_min_offset covers them too.
  std::vector<KeptWindow> kept_windows;
  int kept_columns = 0;
  size_t column_count() const { return variables.size() + static_cast<size_t>(kept_columns); }
  int max_value_stack = 0;
  // Truths of scratch: enough for every condition program at once, as they may nest.
  int max_condition_stack = 0;
  std::vector<ActionCode> actions;
};

// Whether an aggregate ranges over `all` or `component()`: facts of the snapshot of a step
// (docs/design.md §4c), read with no lag, so a host decides them only once every module has
// recorded that step.
inline bool reads_step_snapshot(const Program& p) {
  return std::any_of(p.aggregates.begin(), p.aggregates.end(),
                     [](const AggregateCode& a) { return a.domain == Domain::All || a.domain == Domain::Component; });
}

// Whether an aggregate ranges over `within()` or `component()`: it reads the neighbour lists of
// modules past a module's own neighbours (over ranks, past the window a rank holds).
inline bool reads_far_lists(const Program& p) {
  return std::any_of(p.aggregates.begin(), p.aggregates.end(), [](const AggregateCode& a) {
    return a.domain == Domain::Within || a.domain == Domain::Component;
  });
}

}  // namespace dw::watch
