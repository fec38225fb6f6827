#include "watch/binding_search.h"

#include <algorithm>
#include <cstring>

#include "watch/chunked_copy.h"

namespace dw::watch {

void action_values(const StepView& view, const Program& p, std::span<const uint32_t> ids, std::vector<Value>& out) {
  out.clear();
  if (p.actions.empty()) return;
  const size_t k = static_cast<size_t>(p.slot_count());
  for (size_t at = 0; at + k <= ids.size(); at += k)
    for (const ActionCode& a : p.actions)
      out.push_back(a.value == kNoCode ? known_value(0) : view.value(a.value, ids.data() + at));
}

BindingSearch::BindingSearch(const Program& p, const Optimizations& o, uint64_t budget, uint32_t modules)
    : program_(p), optimizations_(o), live_budget_(budget), modules_(modules) {
  const size_t k = static_cast<size_t>(p.slot_count());
  const size_t leaves = p.leaves.size();
  binding_.resize(k + kCopyChunk);  // slack for chunked copies
  leaf_stride_ = static_cast<uint32_t>((leaves + kByteChunk - 1) / kByteChunk * kByteChunk);
  leaves_.resize((k + 1) * leaf_stride_ + kByteChunk);
  pending_.assign(k, 0);
  for (size_t slot = 0; slot < k; ++slot)
    for (size_t later = slot + 1; later < k; ++later)
      if (!p.slots[later].leaves.empty()) pending_[slot] = kFalse;  // an unknown leaf may be false
  stack_.resize(static_cast<size_t>(p.max_stack));
  trial_.resize(leaves);
  candidates_.resize(k);
  mark_.assign(modules, 0);
  slot_count_ = static_cast<uint32_t>(k);
  own_conjunction_ = p.shape == Program::Shape::Conjunction;
  for (const SlotProgram& sp : p.slots) own_conjunction_ &= sp.carried_leaves.empty();
  for (uint32_t slot = 0; slot < k; ++slot) {
    Level lv;
    lv.slot = slot;
    lv.program = &p.slots[slot];
    lv.last = slot + 1 == k;
    lv.cull = o.neighbor_culling && !lv.program->cull_leaves.empty();
    lv.conjunction = p.shape == Program::Shape::Conjunction;
    lv.own_last = lv.last && slot > 0 && lv.conjunction && !lv.cull && lv.program->carried_leaves.empty();
    levels_.push_back(lv);
  }
}

void BindingSearch::search(const StepView& view, GroupShape shape, std::span<const uint32_t> first, StepStats& stats,
                           MatchBuffer& out) {
  view_ = &view;
  shape_ = shape;
  group_ = {};
  stats_ = &stats;
  out_ = &out;
  std::fill(leaves_.begin(), leaves_.begin() + static_cast<ptrdiff_t>(program_.leaves.size()), kUnknown);
  candidates_[0].assign(first.begin(), first.end());
  extend(0, {});
}

void BindingSearch::assign(const StepView& view, std::span<const uint32_t> group, StepStats& stats, MatchBuffer& out) {
  view_ = &view;
  shape_ = GroupShape::Any;
  group_ = group;
  stats_ = &stats;
  out_ = &out;
  // Which members may take each slot: with early termination, only those whose own leaves there
  // leave the expression not false (a member that may take none makes the group match nothing).
  const uint32_t k = static_cast<uint32_t>(program_.slot_count());
  const uint32_t all_members = k == 32 ? ~0u : (1u << group.size()) - 1;
  uint32_t covered = 0;
  const uint32_t all_slots = k == 32 ? ~0u : (1u << k) - 1;
  std::fill(takers_, takers_ + k, 0u);
  std::fill(satisfiers_, satisfiers_ + k, 0u);
  for (uint32_t i = 0; i < group.size(); ++i) {
    const uint32_t slots = optimizations_.early_termination ? view.fillable(group[i]) : all_slots;
    if (slots == 0) return;
    covered |= slots;
    for (uint32_t bits = slots; bits != 0; bits &= bits - 1) takers_[__builtin_ctz(bits)] |= 1u << i;
    for (uint32_t bits = view.satisfied(group[i]); bits != 0; bits &= bits - 1)
      satisfiers_[__builtin_ctz(bits)] |= 1u << i;
  }
  if (covered != all_slots) return;
  if (own_conjunction_ && optimizations_.early_termination) return assign_own(0, all_members, true);
  std::fill(leaves_.begin(), leaves_.begin() + static_cast<ptrdiff_t>(program_.leaves.size()), kUnknown);
  assign_slot(0, all_members, {});
}

// Kept out of line: the string work would otherwise weigh on every node of the search.
[[gnu::noinline, gnu::cold]] void BindingSearch::over_budget() {
  stop_reason_ =
      "more than " + std::to_string(live_budget_) + " PatternMatchers at watch step " + std::to_string(view_->t());
}

void BindingSearch::next_generation() {
  if (++generation_ == 0) {
    std::fill(mark_.begin(), mark_.end(), 0);
    generation_ = 1;
  }
}

[[gnu::always_inline]] inline BindingSearch::Level BindingSearch::level(uint32_t slot, Fold decided) const {
  Level lv = levels_[slot];
  lv.decided = decided;
  // Pointers made here, not kept: a copy of the search has leaves of its own.
  lv.parent = leaves_.data() + slot * leaf_stride_;
  lv.child = const_cast<Truth*>(leaves_.data()) + (slot + 1) * leaf_stride_;
  return lv;
}

// Module c takes the level's slot: counts it, decides the leaves the slot completes, and reports
// a match at the last slot. Returns whether to go deeper (false also when the search stopped).
[[gnu::always_inline]] inline bool BindingSearch::take(const Level& lv, uint32_t c, Fold& decided) {
  const uint32_t slot = lv.slot;
  if (lv.cull && culled(slot, c, lv.parent)) return false;
  StepStats& st = *stats_;
  binding_[slot] = c;
  ++st.live_by_filled[slot + 1];
  ++st.live;
  ++st.created;
  if (live_budget_ != 0 && st.created > live_budget_) {
    over_budget();
    return false;
  }
  // Plain pointers: stores through Truth* (a char type) could alias a vector's own fields.
  const SlotProgram& sp = *lv.program;
  const uint16_t* own = sp.own_leaves.data();
  const uint16_t* own_end = own + sp.own_leaves.size();
  const uint16_t* carried = sp.carried_leaves.data();
  const uint16_t* carried_end = carried + sp.carried_leaves.size();
  const Truth* own_truth = view_->own_truth();
  const uint32_t modules = modules_;
  const Truth* parent = lv.parent;
  Truth* child = lv.child;
  Truth result;
  if (lv.conjunction) {
    // The leaves decided before this slot come folded into (all, any); each candidate only folds
    // in its own, and leaves decided at later slots are unknown (pending_). The last slot never
    // writes a child level.
    Truth all = lv.decided.all, any = lv.decided.any;
    if (!lv.last) copy_bytes(child, parent, leaf_stride_);
    for (const uint16_t* l = own; l != own_end; ++l) {
      const Truth v = own_truth[*l * modules + c];
      all &= v;
      any |= v;
      if (!lv.last) child[*l] = v;
    }
    for (const uint16_t* l = carried; l != carried_end; ++l) {
      const Truth v = view_->decide(*l, binding_.data());
      all &= v;
      any |= v;
      if (!lv.last) child[*l] = v;
    }
    decided = {all, any};
    result = static_cast<Truth>((all & 1) | ((any | pending_[slot]) & 2));
  } else {
    copy_bytes(child, parent, leaf_stride_);
    for (const uint16_t* l = own; l != own_end; ++l) child[*l] = own_truth[*l * modules + c];
    for (const uint16_t* l = carried; l != carried_end; ++l) child[*l] = view_->decide(*l, binding_.data());
    result = program_.evaluate(child, stack_.data());
  }
  if (lv.last) {
    if (result == kTrue) {
      ++st.matches;
      out_->add(binding_.data(), slot + 1, c);
    }
    return false;
  }
  return !(result == kFalse && optimizations_.early_termination);
}

// Chain and Ordered: fills `slot` with each candidate in turn and goes deeper while the
// expression can still hold.
void BindingSearch::extend(uint32_t slot, Fold decided) {
  if (levels_[slot].own_last) return finish_own(slot, decided);
  if (slot > 0) {
    // Candidates: not yet bound, present neighbours at t of the slot before (Chain) or of any
    // slot filled so far (Ordered).
    std::vector<uint32_t>& cands = candidates_[slot];
    cands.clear();
    next_generation();
    for (uint32_t j = 0; j < slot; ++j) mark_[binding_[j]] = generation_;
    const StepHistory::Graph& now = *view_->now();
    for (uint32_t j = shape_ == GroupShape::Chain ? slot - 1 : 0; j < slot; ++j)
      for (uint32_t n : now.neighbors(binding_[j])) {
        if (mark_[n] == generation_ || !now.present[n]) continue;
        mark_[n] = generation_;
        cands.push_back(n);
      }
  }
  const Level lv = level(slot, decided);
  for (uint32_t c : candidates_[slot]) {
    Fold next;
    if (take(lv, c, next)) extend(slot + 1, next);
    if (stopped()) return;
  }
}

// extend at the last slot of a conjunction whose last slot only reads its module's own state
// (Fig. 6 and most of Table I): each candidate counts and matches when its own leaves there are
// true, so the candidates are taken as they are found. The same candidates in the same order as
// extend and take, and the same statistics.
void BindingSearch::finish_own(uint32_t slot, Fold decided) {
  next_generation();
  uint32_t* binding = binding_.data();
  for (uint32_t j = 0; j < slot; ++j) mark_[binding[j]] = generation_;
  // The binding matches when every leaf is true: those decided so far, and the slot's own.
  const bool so_far = (decided.all & 1) != 0 && (decided.any & 2) == 0;
  const Truth* own = view_->own_slot_truth(slot);
  const StepHistory::Graph& now = *view_->now();
  uint64_t taken = 0, matches = 0;
  for (uint32_t j = shape_ == GroupShape::Chain ? slot - 1 : 0; j < slot; ++j)
    for (uint32_t n : now.neighbors(binding[j])) {
      if (mark_[n] == generation_ || !now.present[n]) continue;
      mark_[n] = generation_;
      ++taken;
      if (!so_far || own[n] != kTrue) continue;
      out_->add(binding, slot + 1, n);
      ++matches;
    }
  StepStats& st = *stats_;
  st.live_by_filled[slot + 1] += taken;
  st.live += taken;
  st.created += taken;
  st.matches += matches;
  // Checked once for the slot's candidates: a step over the budget reports nothing anyway.
  if (live_budget_ != 0 && st.created > live_budget_) over_budget();
}

// Any, within one group: `slot` takes each unbound member that may take it (bits of `unbound`).
// Early termination within a group: once `slot` is taken, every later slot must keep a member
// (bits of `left`) that may take it.
[[gnu::always_inline]] inline bool BindingSearch::completable(uint32_t slot, uint32_t left) const {
  for (uint32_t later = slot + 1; later < slot_count_; ++later)
    if ((left & takers_[later]) == 0) return false;
  return true;
}

void BindingSearch::assign_slot(uint32_t slot, uint32_t unbound, Fold decided) {
  const Level lv = level(slot, decided);
  for (uint32_t bits = unbound & takers_[slot]; bits != 0; bits &= bits - 1) {
    const uint32_t i = static_cast<uint32_t>(__builtin_ctz(bits));
    const uint32_t left = unbound & ~(1u << i);
    if (!completable(slot, left)) continue;
    Fold next;
    if (take(lv, group_[i], next)) assign_slot(slot + 1, left, next);
    if (stopped()) return;
  }
}

// assign_slot for a conjunction of own leaves: with early termination every member taking a slot
// leaves it not false, so a binding is true exactly when each member satisfies its slot. The same
// bindings are visited and counted as by assign_slot; only the leaves are not written.
void BindingSearch::assign_own(uint32_t slot, uint32_t unbound, bool satisfied) {
  const uint32_t k = slot_count_;
  StepStats& st = *stats_;
  for (uint32_t bits = unbound & takers_[slot]; bits != 0; bits &= bits - 1) {
    const uint32_t i = static_cast<uint32_t>(__builtin_ctz(bits));
    const uint32_t left = unbound & ~(1u << i);
    if (!completable(slot, left)) continue;
    binding_[slot] = group_[i];
    ++st.live_by_filled[slot + 1];
    ++st.live;
    ++st.created;
    if (live_budget_ != 0 && st.created > live_budget_) {
      over_budget();
      return;
    }
    const bool all = satisfied && (satisfiers_[slot] >> i & 1);
    if (slot + 1 < k) {
      assign_own(slot + 1, left, all);
      if (stopped()) return;
    } else if (all) {
      ++st.matches;
      out_->add(binding_.data(), k, group_[i]);
    }
  }
}

// Neighbour culling (paper §IV-C): would the expression be false whatever else fills, if
// `candidate` took `slot`? Only neighbor(x slot) terms with x already filled can tell.
bool BindingSearch::culled(uint32_t slot, uint32_t candidate, const Truth* leaves) {
  std::memcpy(trial_.data(), leaves, trial_.size());
  for (uint16_t l : program_.slots[slot].cull_leaves) {
    const Leaf& leaf = program_.leaves[l];
    trial_[l] = view_->neighbor(binding_[static_cast<size_t>(leaf.x)], leaf.offset, candidate);
  }
  return program_.evaluate(trial_.data(), stack_.data()) == kFalse;
}

}  // namespace dw::watch
