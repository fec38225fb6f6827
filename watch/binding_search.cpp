#include "watch/binding_search.h"

#include <algorithm>
#include <cstring>

#include "watch/chunked_copy.h"

namespace dw::watch {

BindingSearch::BindingSearch(const Program& p, const Optimizations& o, uint64_t budget, uint32_t modules)
    : program_(p), optimizations_(o), live_budget_(budget), modules_(modules) {
  const size_t k = static_cast<size_t>(p.slot_count());
  const size_t leaves = p.leaves.size();
  binding_.resize(k + kCopyChunk);  // slack for chunked copies
  leaf_stride_ = static_cast<uint32_t>((leaves + kByteChunk - 1) / kByteChunk * kByteChunk);
  leaves_.resize((k + 1) * leaf_stride_ + kByteChunk);
  decided_at_.assign(k * leaves, 0);
  for (size_t slot = 0; slot < k; ++slot)
    for (uint16_t l : p.slots[slot].leaves) decided_at_[slot * leaves + l] = 1;
  stack_.resize(static_cast<size_t>(p.max_stack));
  trial_.resize(leaves);
  candidates_.resize(k);
  mark_.assign(modules, 0);
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
  extend(0);
}

void BindingSearch::assign(const StepView& view, std::span<const uint32_t> group, StepStats& stats, MatchBuffer& out) {
  view_ = &view;
  shape_ = GroupShape::Any;
  group_ = group;
  stats_ = &stats;
  out_ = &out;
  std::fill(leaves_.begin(), leaves_.begin() + static_cast<ptrdiff_t>(program_.leaves.size()), kUnknown);
  candidates_[0].assign(group.begin(), group.end());
  extend(0);
}

void BindingSearch::next_generation() {
  if (++generation_ == 0) {
    std::fill(mark_.begin(), mark_.end(), 0);
    generation_ = 1;
  }
}

// Fills `slot` with each candidate in turn and goes deeper while the expression can still hold.
void BindingSearch::extend(uint32_t slot) {
  const uint32_t k = static_cast<uint32_t>(program_.slot_count());
  const SlotProgram& sp = program_.slots[slot];
  const Truth* parent = leaves_.data() + slot * leaf_stride_;
  Truth* child = leaves_.data() + (slot + 1) * leaf_stride_;
  StepStats& st = *stats_;

  if (slot > 0) {
    // Candidates: not yet bound, and the group's members (Any) or present neighbours at t of the
    // slot before (Chain) or of any slot filled so far (Ordered).
    std::vector<uint32_t>& cands = candidates_[slot];
    cands.clear();
    next_generation();
    for (uint32_t j = 0; j < slot; ++j) mark_[binding_[j]] = generation_;
    if (shape_ == GroupShape::Any) {
      for (uint32_t m : group_)
        if (mark_[m] != generation_) cands.push_back(m);
    } else {
      const StepHistory::Graph& now = *view_->now();
      for (uint32_t j = shape_ == GroupShape::Chain ? slot - 1 : 0; j < slot; ++j)
        for (uint32_t n : now.neighbors(binding_[j])) {
          if (mark_[n] == generation_ || !now.present[n]) continue;
          mark_[n] = generation_;
          cands.push_back(n);
        }
    }
  }

  // Plain pointers: stores through Truth* (a char type) could alias a vector's own fields.
  const uint16_t* own = sp.own_leaves.data();
  const uint16_t* own_end = own + sp.own_leaves.size();
  const uint16_t* carried = sp.carried_leaves.data();
  const uint16_t* carried_end = carried + sp.carried_leaves.size();
  const Truth* own_truth = view_->own_truth();
  const uint32_t modules = modules_;
  const bool last = slot + 1 == k;
  const bool cull = optimizations_.neighbor_culling && !sp.cull_leaves.empty();
  // For a conjunction, the leaves decided before this slot fold once into (all, any); each
  // candidate only folds in its own leaves, and the last slot never writes a child level.
  const bool conjunction = program_.shape == Program::Shape::Conjunction;
  Truth base_all = 1, base_any = 0;
  if (conjunction) {
    const uint8_t* decided_here = decided_at_.data() + slot * program_.leaf_count;
    for (uint32_t l = 0; l < program_.leaf_count; ++l)
      if (!decided_here[l]) {
        base_all &= parent[l];
        base_any |= parent[l];
      }
  }
  for (uint32_t c : candidates_[slot]) {
    if (stopped()) return;
    if (cull && culled(slot, c, parent)) continue;
    binding_[slot] = c;
    ++st.live_by_filled[slot + 1];
    ++st.live;
    ++st.created;
    if (live_budget_ != 0 && st.created > live_budget_) {
      stop_reason_ =
          "more than " + std::to_string(live_budget_) + " PatternMatchers at watch step " + std::to_string(view_->t());
      return;
    }
    Truth result;
    if (conjunction) {
      Truth all = base_all, any = base_any;
      if (!last) copy_bytes(child, parent, leaf_stride_);
      for (const uint16_t* l = own; l != own_end; ++l) {
        const Truth v = own_truth[*l * modules + c];
        all &= v;
        any |= v;
        if (!last) child[*l] = v;
      }
      for (const uint16_t* l = carried; l != carried_end; ++l) {
        const Truth v = view_->decide(*l, binding_.data());
        all &= v;
        any |= v;
        if (!last) child[*l] = v;
      }
      result = static_cast<Truth>((all & 1) | (any & 2));
    } else {
      copy_bytes(child, parent, leaf_stride_);
      for (const uint16_t* l = own; l != own_end; ++l) child[*l] = own_truth[*l * modules + c];
      for (const uint16_t* l = carried; l != carried_end; ++l) child[*l] = view_->decide(*l, binding_.data());
      result = program_.evaluate(child, stack_.data());
    }
    if (last) {
      if (result == kTrue) {
        ++st.matches;
        out_->add(binding_.data(), k);
      }
      continue;
    }
    if (result == kFalse && optimizations_.early_termination) continue;
    extend(slot + 1);
  }
}

bool BindingSearch::may_fill(const StepView& view, uint32_t module) {
  for (const SlotProgram& sp : program_.slots) {
    std::fill(trial_.begin(), trial_.end(), kUnknown);
    for (uint16_t l : sp.own_leaves) trial_[l] = view.own(l, module);
    if (program_.evaluate(trial_.data(), stack_.data()) != kFalse) return true;
  }
  return false;
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
