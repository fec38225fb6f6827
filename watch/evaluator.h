// Runs a Program's value code (docs/design.md §4b) over whatever holds the state a reading compares:
// exact int64 arithmetic in three values, where an unknown operand, a division or remainder by
// zero, and any result outside int64 are Unknown (never a wrap, never a trap).
//
// A Reader gives what the code reads, as the detector at hand knows it:
//   Value term(const ValueInstr&)            slot.variable at its offset (a cell, or own history)
//   int open(const AggregateCode&)           the aggregate's neighbours: their count, -1 when unknown
//   Value bound(int i, const ValueInstr&)    neighbour i's variable, offset from the aggregate's step
//   Truth bound_adjacent(int i, int off, uint32_t y)   y in N(neighbour i, step + off)
//   uint32_t bound_id(int i)                 neighbour i's module
//   uint32_t slot_module(int slot)           the module filling a slot
//   Truth slot_adjacent(const ConditionTest&, uint32_t y)   y in N(slot x's module, now_x + off)
//   int64_t now(int slot)                    the slot's "now" (docs/design.md §4c: where windows clip)
//   int expand(int i)                        component: neighbour i's present neighbours not yet
//                                            seen become elements too; the count of elements
//   int keep(const std::vector<uint8_t>&)    component: only the elements marked stay; their count
// and may give, to count `count(n in D: n.x OP c)` without reading the elements one by one:
//   bool count_where(const ValueInstr&, CompareOp, int64_t c, int count, Value& out)
//                                            false when it cannot (then they are read one by one)
// A term or bound read of kIdVariable is id(m): the module's id when present at that step.
// Aggregates do not nest, so a reader has at most one open at a time.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "watch/kleene.h"
#include "watch/program.h"
#include "watch/value.h"

namespace dw::watch {

// One arithmetic operation, checked (docs/design.md §4b): truncating division, the dividend's sign for
// the remainder, INT64_MIN / -1 unknown and INT64_MIN % -1 zero.
inline Value apply(ValueOp op, Value a, Value b) {
  if (!a.known || ((op != ValueOp::Negate && op != ValueOp::Abs) && !b.known)) return {};
  int64_t r = 0;
  switch (op) {
    case ValueOp::Negate:
      if (a.value == INT64_MIN) return {};
      return known_value(-a.value);
    case ValueOp::Abs:
      if (a.value == INT64_MIN) return {};
      return known_value(a.value < 0 ? -a.value : a.value);
    case ValueOp::Add:
      if (__builtin_add_overflow(a.value, b.value, &r)) return {};
      return known_value(r);
    case ValueOp::Subtract:
      if (__builtin_sub_overflow(a.value, b.value, &r)) return {};
      return known_value(r);
    case ValueOp::Multiply:
      if (__builtin_mul_overflow(a.value, b.value, &r)) return {};
      return known_value(r);
    case ValueOp::Divide:
      if (b.value == 0 || (a.value == INT64_MIN && b.value == -1)) return {};
      return known_value(a.value / b.value);
    case ValueOp::Remainder:
      if (b.value == 0) return {};
      if (b.value == -1) return known_value(0);
      return known_value(a.value % b.value);
    case ValueOp::Min: return known_value(a.value < b.value ? a.value : b.value);
    case ValueOp::Max: return known_value(a.value > b.value ? a.value : b.value);
    default: return {};
  }
}

inline Truth compare_values(CompareOp op, Value a, Value b) {
  if (!a.known || !b.known) return kUnknown;
  return truth_of(holds(op, a.value, b.value));
}

// Of the modules `ids`, how many have `x OP c`, x read at values[id - first] (known[id - first]):
// false when any is unknown. What a reader's count_where does once it has the variable's row.
inline bool count_holding(std::span<const uint32_t> ids, uint32_t first, const int64_t* values, const uint8_t* known,
                          CompareOp op, int64_t c, int64_t& n) {
  uint32_t all_known = 1;
  int64_t total = 0;
  with_compare(op, [&](auto holds_op) {
    for (uint32_t id : ids) {
      all_known &= known[id - first];
      total += holds_op(values[id - first], c);
    }
  });
  n = total;
  return all_known != 0;
}

// Scratch for evaluation: sized once per Program, reused for every evaluation.
struct EvaluatorScratch {
  EvaluatorScratch() = default;
  explicit EvaluatorScratch(const Program& p)
      : values(static_cast<size_t>(p.max_value_stack) + p.aggregates.size() + p.truths.size() + 1),
        truths(static_cast<size_t>(p.max_condition_stack) + 1) {}
  std::vector<Value> values;
  std::vector<Truth> truths;
};

template <class Reader>
class Evaluator {
 public:
  Evaluator(const Program& p, Reader& r, EvaluatorScratch& s) : p_(p), r_(r), s_(s) {}

  // Condition program `truth` (Program::truths), outside any aggregate.
  Truth condition_program(uint32_t truth) { return logic(p_.truths[truth], p_.truth_depths[truth], 0, -1); }

  // A leaf of kind Expression.
  Truth leaf(const Leaf& l) { return compare_values(l.op, value(l.lhs_code, 0, -1), value(l.rhs_code, 0, -1)); }

  // Value code `code`, its stack from `base`; `neighbor` is the aggregate's current one (-1 outside).
  Value value(uint32_t code, size_t base, int neighbor) {
    Value* stack = s_.values.data() + base;
    size_t sp = 0;
    for (const ValueInstr& in : p_.codes[code]) {
      switch (in.op) {
        case ValueOp::Constant: stack[sp++] = known_value(in.constant); break;
        case ValueOp::Term: stack[sp++] = r_.term(in); break;
        case ValueOp::Bound: stack[sp++] = r_.bound(neighbor, in); break;
        case ValueOp::Aggregate:
          stack[sp] = aggregate(p_.aggregates[in.index], base + sp + 1);
          ++sp;
          break;
        case ValueOp::Step: stack[sp++] = known_value(r_.now(in.slot) + in.offset); break;
        case ValueOp::Truth: {
          const Truth t = logic(p_.truths[in.index], p_.truth_depths[in.index], base + sp + 1, neighbor);
          stack[sp++] = t == kUnknown ? Value{} : known_value(t == kTrue ? 1 : 0);
          break;
        }
        case ValueOp::Negate:
        case ValueOp::Abs: stack[sp - 1] = apply(in.op, stack[sp - 1], {}); break;
        default:
          --sp;
          stack[sp - 1] = apply(in.op, stack[sp - 1], stack[sp]);
          break;
      }
    }
    return stack[0];
  }

 private:
  Value aggregate(const AggregateCode& a, size_t base) {
    int count = r_.open(a);
    if (count < 0) return {};
    if (a.domain == Domain::Component) count = component(a, base, count);
    if (count < 0) return {};
    switch (a.kind) {
      case AggregateKind::Count: {
        if (a.condition.empty()) return known_value(count);
        if (const ConditionTest* c = read_against_constant(a)) return count_compared(*c, count);
        int64_t n = 0;
        for (int i = 0; i < count; ++i) {
          const Truth t = condition(a, base, i);
          if (t == kUnknown) return {};
          n += t == kTrue;
        }
        return known_value(n);
      }
      case AggregateKind::Sum: {
        // The exact total: Unknown only when it lies outside int64, whatever the order.
        __int128 total = 0;
        for (int i = 0; i < count; ++i) {
          const Value v = value(a.value, base, i);
          if (!v.known) return {};
          total += v.value;
        }
        if (total < std::numeric_limits<int64_t>::min() || total > std::numeric_limits<int64_t>::max()) return {};
        return known_value(static_cast<int64_t>(total));
      }
      case AggregateKind::Min:
      case AggregateKind::Max: {
        if (count == 0) return {};
        Value best;
        for (int i = 0; i < count; ++i) {
          const Value v = value(a.value, base, i);
          if (!v.known) return {};
          if (i == 0 || (a.kind == AggregateKind::Min ? v.value < best.value : v.value > best.value)) best = v;
        }
        return best;
      }
      case AggregateKind::Argmin:
      case AggregateKind::Argmax: return arg_best(a, base, count);
    }
    return {};
  }

  // The condition's one test when it compares an element's variable with a constant
  // (`count(n in D: n.x = 0)`, the commonest): counted without the logic and value programs.
  const ConditionTest* read_against_constant(const AggregateCode& a) const {
    if (a.condition.size() != 1) return nullptr;
    const ConditionTest& t = p_.tests[a.condition[0].leaf];
    if (t.kind != ConditionTest::Kind::Compare) return nullptr;
    const std::vector<ValueInstr>& l = p_.codes[t.lhs];
    const std::vector<ValueInstr>& r = p_.codes[t.rhs];
    const bool plain = l.size() == 1 && l[0].op == ValueOp::Bound && r.size() == 1 && r[0].op == ValueOp::Constant;
    return plain ? &t : nullptr;
  }
  Value count_compared(const ConditionTest& t, int count) {
    const ValueInstr& read = p_.codes[t.lhs][0];
    const int64_t constant = p_.codes[t.rhs][0].constant;
    if constexpr (requires(Value & out) { r_.count_where(read, t.op, constant, count, out); }) {
      // A reader that can find the variable's row once for all the elements.
      if (Value out; r_.count_where(read, t.op, constant, count, out)) return out;
    }
    int64_t n = 0;
    for (int i = 0; i < count; ++i) {
      const Value v = r_.bound(i, read);
      if (!v.known) return {};
      n += holds(t.op, v.value, constant);
    }
    return known_value(n);
  }

  // component(m: c) (docs/design.md §4c), breadth-first from the module (candidate 0, what open gave):
  // a candidate where c is true joins and brings its present neighbours not yet seen as candidates,
  // false stays out, unknown makes the whole unknown (-1). Leaves the members as the elements.
  int component(const AggregateCode& a, size_t base, int count) {
    std::vector<uint8_t> joined;
    for (int i = 0; i < count; ++i) {
      const Truth t = logic(a.member_condition, a.member_depth, base, i);
      if (t == kUnknown) return -1;
      joined.push_back(t == kTrue);
      if (t == kTrue) count = r_.expand(i);
    }
    return r_.keep(joined);
  }

  // The id of the element of least (argmin) or greatest (argmax) value, ties to the least id
  // (docs/design.md §4c); unknown over none, or when any value is unknown.
  Value arg_best(const AggregateCode& a, size_t base, int count) {
    if (count == 0) return {};
    ValueInstr id;
    id.op = ValueOp::Bound;
    id.variable = kIdVariable;
    Value best, best_id;
    for (int i = 0; i < count; ++i) {
      const Value v = value(a.value, base, i);
      const Value m = r_.bound(i, id);
      if (!v.known || !m.known) return {};
      const bool better = a.kind == AggregateKind::Argmin ? v.value < best.value : v.value > best.value;
      if (i == 0 || better || (v.value == best.value && m.value < best_id.value)) {
        best = v;
        best_id = m;
      }
    }
    return best_id;
  }

  Truth condition(const AggregateCode& a, size_t base, int neighbor) {
    return logic(a.condition, a.condition_depth, base, neighbor);
  }

  // Postfix logic over tests, its truths above those of the logic under way (they may nest).
  Truth logic(const std::vector<ExprOp>& ops, int depth, size_t base, int neighbor) {
    Truth* stack = s_.truths.data() + truths_used_;
    truths_used_ += static_cast<size_t>(depth);
    const Truth t = run_logic(ops, stack, [&](uint32_t i) { return test(p_.tests[i], base, neighbor); });
    truths_used_ -= static_cast<size_t>(depth);
    return t;
  }

  Truth test(const ConditionTest& t, size_t base, int neighbor) {
    if (t.kind == ConditionTest::Kind::Compare)
      return compare_values(t.op, value(t.lhs, base, neighbor), value(t.rhs, base, neighbor));
    const uint32_t y = t.y == kBound ? r_.bound_id(neighbor) : r_.slot_module(t.y);
    if (t.x == kBound) return r_.bound_adjacent(neighbor, t.offset, y);
    return r_.slot_adjacent(t, y);
  }

  const Program& p_;
  Reader& r_;
  EvaluatorScratch& s_;
  size_t truths_used_ = 0;
};

template <class Reader>
Evaluator(const Program&, Reader&, EvaluatorScratch&) -> Evaluator<Reader>;

}  // namespace dw::watch
