// A brute-force reading of a watchpoint, written here straight from docs/design.md §4 and §4b and
// independent of watch/program and watch/evaluator: the tree is walked for each binding, values
// are exact (__int128), and every rule of the semantics is spelled out where it applies.
#pragma once

#include <algorithm>
#include <optional>
#include <set>
#include <vector>

#include "test_ensemble.h"
#include "watch/ast.h"

namespace dw::watch::testing {

enum class K { T, F, U };
inline K k_not(K a) { return a == K::U ? K::U : (a == K::T ? K::F : K::T); }
inline K k_and(K a, K b) {
  if (a == K::F || b == K::F) return K::F;
  return a == K::T && b == K::T ? K::T : K::U;
}
inline K k_or(K a, K b) {
  if (a == K::T || b == K::T) return K::T;
  return a == K::F && b == K::F ? K::F : K::U;
}

inline bool adjacent(const TestEnsemble& e, int64_t t, uint32_t from, uint32_t to) {
  const auto& nb = e.nbrs(t, from);
  return std::find(nb.begin(), nb.end(), to) != nb.end();
}

// Evaluates the tree of `ast` for one binding, slot s's "now" at now[s].
class BruteReading {
 public:
  BruteReading(const TestEnsemble& e, const Ast& ast, const std::vector<uint32_t>& binding,
               const std::vector<int64_t>& now)
      : e_(e), ast_(ast), b_(binding), now_(now) {}

  K truth(NodeIndex i) {
    const Node& n = ast_.nodes[i];
    switch (n.kind) {
      case NodeKind::Not: return k_not(truth(n.lhs));
      case NodeKind::And: return k_and(truth(n.lhs), truth(n.rhs));
      case NodeKind::Or: return k_or(truth(n.lhs), truth(n.rhs));
      case NodeKind::Neighbor: {
        const int64_t step = step_of(n.x);
        const uint32_t x = module_of(n.x), y = module_of(n.y);
        if (!e_.present(step, x)) return K::U;
        return adjacent(e_, step, x, y) ? K::T : K::F;
      }
      case NodeKind::Compare: {
        const auto a = value(n.lhs), b = value(n.rhs);
        if (!a || !b) return K::U;
        bool r = false;
        switch (n.op) {
          case CompareOp::Less: r = *a < *b; break;
          case CompareOp::Greater: r = *a > *b; break;
          case CompareOp::Equal: r = *a == *b; break;
          case CompareOp::NotEqual: r = *a != *b; break;
          case CompareOp::GreaterEqual: r = *a >= *b; break;
          case CompareOp::LessEqual: r = *a <= *b; break;
        }
        return r ? K::T : K::F;
      }
      default: return K::U;
    }
  }

  // An integer expression: nullopt is U.
  std::optional<int64_t> value(NodeIndex i) {
    const Node& n = ast_.nodes[i];
    auto fit = [](__int128 v) -> std::optional<int64_t> {
      if (v < INT64_MIN || v > INT64_MAX) return std::nullopt;
      return static_cast<int64_t>(v);
    };
    switch (n.kind) {
      case NodeKind::Integer: return n.value;
      case NodeKind::Variable: return e_.value(step_of(n.x), module_of(n.x), n.name);
      case NodeKind::Negate: {
        const auto a = value(n.lhs);
        if (!a) return std::nullopt;
        return fit(-static_cast<__int128>(*a));
      }
      case NodeKind::Abs: {
        const auto a = value(n.lhs);
        if (!a) return std::nullopt;
        return fit(*a < 0 ? -static_cast<__int128>(*a) : static_cast<__int128>(*a));
      }
      case NodeKind::Add:
      case NodeKind::Subtract:
      case NodeKind::Multiply:
      case NodeKind::Divide:
      case NodeKind::Remainder:
      case NodeKind::Min:
      case NodeKind::Max: {
        const auto a = value(n.lhs), b = value(n.rhs);
        if (!a || !b) return std::nullopt;
        const __int128 x = *a, y = *b;
        switch (n.kind) {
          case NodeKind::Add: return fit(x + y);
          case NodeKind::Subtract: return fit(x - y);
          case NodeKind::Multiply: return fit(x * y);
          case NodeKind::Divide: return y == 0 ? std::nullopt : fit(x / y);     // truncates toward zero
          case NodeKind::Remainder: return y == 0 ? std::nullopt : fit(x % y);  // the dividend's sign
          case NodeKind::Min: return std::min(*a, *b);
          default: return std::max(*a, *b);
        }
      }
      case NodeKind::Aggregate: return aggregate(n);
      default: return std::nullopt;
    }
  }

 private:
  int64_t step_of(const ModuleRef& m) const { return m.bound ? s_ + m.offset : now_[m.slot] + m.offset; }
  uint32_t module_of(const ModuleRef& m) const { return m.bound ? n_ : b_[m.slot]; }

  std::optional<int64_t> aggregate(const Node& a) {
    const int64_t s = now_[a.x.slot] + a.x.offset;
    const uint32_t m = b_[a.x.slot];
    if (!e_.present(s, m)) return std::nullopt;
    std::set<uint32_t> members;  // N(m, s) as a set, of the neighbours present at s
    for (uint32_t u : e_.nbrs(s, m))
      if (e_.present(s, u)) members.insert(u);
    const int64_t saved_s = s_;
    const uint32_t saved_n = n_;
    s_ = s;
    bool unknown = false;
    __int128 total = 0;
    int64_t count = 0;
    std::optional<int64_t> best;
    for (uint32_t u : members) {
      n_ = u;
      if (a.aggregate == AggregateKind::Count) {
        if (a.lhs == kNoNode) {
          ++count;
          continue;
        }
        const K t = truth(a.lhs);
        unknown |= t == K::U;
        count += t == K::T;
        continue;
      }
      const auto v = value(a.lhs);
      if (!v) {
        unknown = true;
        continue;
      }
      total += *v;
      if (!best || (a.aggregate == AggregateKind::Min ? *v < *best : *v > *best)) best = *v;
    }
    s_ = saved_s;
    n_ = saved_n;
    if (unknown) return std::nullopt;
    switch (a.aggregate) {
      case AggregateKind::Count: return count;
      case AggregateKind::Sum:
        if (total < INT64_MIN || total > INT64_MAX) return std::nullopt;
        return static_cast<int64_t>(total);
      default: return best;  // none: U
    }
  }

  const TestEnsemble& e_;
  const Ast& ast_;
  const std::vector<uint32_t>& b_;
  const std::vector<int64_t>& now_;
  int64_t s_ = 0;   // the aggregate's step
  uint32_t n_ = 0;  // the bound neighbour
};

inline K evaluate(const Ast& ast, NodeIndex i, const TestEnsemble& e, const std::vector<uint32_t>& binding,
                  const std::vector<int64_t>& now) {
  return BruteReading(e, ast, binding, now).truth(i);
}

// Every k-permutation of the modules, passed to fn.
template <class Fn>
void permutations(uint32_t modules, size_t k, Fn&& fn) {
  std::vector<uint32_t> b(k);
  std::vector<bool> used(modules);
  auto rec = [&](auto&& self, size_t i) -> void {
    if (i == k) return fn(b);
    for (uint32_t m = 0; m < modules; ++m) {
      if (used[m]) continue;
      used[m] = true;
      b[i] = m;
      self(self, i + 1);
      used[m] = false;
    }
  };
  rec(rec, 0);
}

}  // namespace dw::watch::testing
