#include "watch/centralized_detector.h"

#include "watch/chunked_copy.h"

#include <algorithm>
#include <chrono>
#include <cstring>

namespace dw::watch {

CentralizedDetector::CentralizedDetector(const Watchpoint& w, const Universe& u, DetectorOptions options,
                                         MatchSink sink)
    : Detector(u, std::move(sink)), program_(w.program), options_(options), columns_(variable_columns(w.program, u)) {
  const bool spans = options.optimizations.temporal_spans;
  history_.resize(program_.variables.size());
  for (size_t v = 0; v < history_.size(); ++v)
    history_[v].configure(spans ? program_.extent_plus - program_.variable_min_offset[v] + 1 : 0);
  graphs_.configure(spans ? program_.extent_plus - program_.min_neighbor_offset + 1 : 0);
  const size_t k = static_cast<size_t>(program_.slot_count());
  const size_t leaves = program_.leaves.size();
  lhs_.resize(leaves);
  rhs_.resize(leaves);
  graph_at_offset_.resize(static_cast<size_t>(program_.extent_plus - program_.min_neighbor_offset) + 1);
  binding_.resize(k + kCopyChunk);  // slack for chunked copies
  leaf_stride_ = static_cast<uint32_t>((leaves + kByteChunk - 1) / kByteChunk * kByteChunk);
  leaves_.resize((k + 1) * leaf_stride_ + kByteChunk);
  own_truth_.resize(leaves * u.module_count());
  decided_at_.assign(k * leaves, 0);
  for (size_t slot = 0; slot < k; ++slot)
    for (uint16_t l : program_.slots[slot].leaves) decided_at_[slot * leaves + l] = 1;
  stack_.resize(static_cast<size_t>(program_.max_stack));
  trial_.resize(leaves);
  candidates_.resize(k);
  mark_.assign(u.module_count(), 0);
}

void CentralizedDetector::record(const Frame& frame) {
  const uint32_t m_count = universe_.module_count();
  for (size_t v = 0; v < history_.size(); ++v) {
    Column& col = history_[v].write(frame.step);
    col.value.resize(m_count);
    col.known.resize(m_count);
    const int c = columns_[v];
    for (uint32_t m = 0; m < m_count; ++m) {
      const size_t at = static_cast<size_t>(m) * frame.variable_count + static_cast<size_t>(c);
      const bool known = c >= 0 && frame.present[m] && frame.has_value[at];
      col.known[m] = known;
      col.value[m] = known ? frame.values[at] : 0;
    }
  }
  Graph& g = graphs_.write(frame.step);
  g.present.assign(frame.present.begin(), frame.present.end());
  g.begin.assign(frame.nbr_begin.begin(), frame.nbr_begin.end());
  g.ids.assign(frame.nbrs.begin(), frame.nbrs.end());
}

size_t CentralizedDetector::bytes() const {
  size_t n = sizeof(*this);
  for (const StepRing<Column>& ring : history_)
    for (const Column& c : ring.items()) n += c.value.capacity() * sizeof(int64_t) + c.known.capacity();
  for (const Graph& g : graphs_.items())
    n += g.present.capacity() + (g.begin.capacity() + g.ids.capacity()) * sizeof(uint32_t);
  return n + (own_truth_.capacity() + leaves_.capacity()) * sizeof(Truth) + matches_.capacity() * sizeof(uint32_t);
}

void CentralizedDetector::observe(const Frame& frame) {
  if (stats_.stopped) return;
  const auto started = std::chrono::steady_clock::now();
  record(frame);
  const int64_t t = frame.step - program_.extent_plus;
  if (t < 0) return;
  step_ = StepStats{};
  step_.step = t;
  step_.live_by_filled.assign(static_cast<size_t>(program_.slot_count()) + 1, 0);
  match_values_ = 0;
  run_step(t);
  // The step that went over the budget was cut short: none of it is reported (as distributed).
  if (stats_.stopped) return;
  step_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  stats_.add(step_);
  uint64_t held = static_cast<uint64_t>(graphs_.held());
  for (const auto& ring : history_) held += static_cast<uint64_t>(ring.held()) * universe_.module_count();
  stats_.history_values = held;
  emit(t, {matches_.data(), match_values_});
}

Truth CentralizedDetector::neighbor(uint32_t x_module, int offset, uint32_t y_module) const {
  const Graph* g = graph_at_offset_[static_cast<size_t>(offset - program_.min_neighbor_offset)];
  if (g == nullptr || !g->present[x_module]) return kUnknown;
  const uint32_t* b = g->ids.data() + g->begin[x_module];
  const uint32_t* e = g->ids.data() + g->begin[x_module + 1];
  return truth_of(std::find(b, e, y_module) != e);
}

// A comparison leaf with its left operand read from module lm and its right from rm.
Truth CentralizedDetector::compare(const Leaf& leaf, uint32_t i, uint32_t lm, uint32_t rm) const {
  const ResolvedTerm& l = lhs_[i];
  if (l.value == nullptr || !l.known[lm]) return kUnknown;
  int64_t b = leaf.constant;
  if (!leaf.rhs_is_constant) {
    const ResolvedTerm& r = rhs_[i];
    if (r.value == nullptr || !r.known[rm]) return kUnknown;
    b = r.value[rm];
  }
  return truth_of(holds(leaf.op, l.value[lm], b));
}

Truth CentralizedDetector::decide(const Leaf& leaf, uint32_t i) const {
  if (leaf.kind == LeafKind::Neighbor)
    return neighbor(binding_[static_cast<size_t>(leaf.x)], leaf.offset, binding_[static_cast<size_t>(leaf.y)]);
  const uint32_t rm = leaf.rhs_is_constant ? 0 : binding_[static_cast<size_t>(leaf.rhs.slot)];
  return compare(leaf, i, binding_[static_cast<size_t>(leaf.lhs.slot)], rm);
}

void CentralizedDetector::run_step(int64_t t) {
  t_ = t;
  now_ = graphs_.find(t);
  // Resolve every term's step once, so the inner loop only indexes arrays.
  auto resolve = [&](const TermRef& term) {
    ResolvedTerm r;
    if (const Column* c = history_[static_cast<size_t>(term.variable)].find(t + term.offset)) {
      r.value = c->value.data();
      r.known = c->known.data();
    }
    return r;
  };
  for (size_t i = 0; i < program_.leaves.size(); ++i) {
    const Leaf& leaf = program_.leaves[i];
    if (leaf.kind != LeafKind::Compare) continue;
    lhs_[i] = resolve(leaf.lhs);
    rhs_[i] = leaf.rhs_is_constant ? ResolvedTerm{} : resolve(leaf.rhs);
  }
  for (size_t o = 0; o < graph_at_offset_.size(); ++o)
    graph_at_offset_[o] = graphs_.find(t + program_.min_neighbor_offset + static_cast<int64_t>(o));

  // A leaf that reads one slot only has the same truth for every binding that puts module m in
  // that slot: decide it once per module (SlotProgram::own_leaves).
  const uint32_t modules = universe_.module_count();
  for (const SlotProgram& sp : program_.slots)
    for (uint16_t l : sp.own_leaves)
      for (uint32_t m = 0; m < modules; ++m) own_truth_[l * modules + m] = compare(program_.leaves[l], l, m, m);

  std::fill(leaves_.begin(), leaves_.begin() + static_cast<ptrdiff_t>(program_.leaves.size()), kUnknown);
  std::vector<uint32_t>& first = candidates_[0];
  first.clear();
  for (uint32_t m = 0; m < universe_.module_count(); ++m)
    if (now_->present[m]) first.push_back(m);
  extend(0);
}

// Fills `slot` with each candidate in turn and goes deeper while the expression can still hold.
void CentralizedDetector::extend(uint32_t slot) {
  const uint32_t k = static_cast<uint32_t>(program_.slot_count());
  const uint32_t modules = universe_.module_count();
  const SlotProgram& sp = program_.slots[slot];
  const Truth* parent = leaves_.data() + slot * leaf_stride_;
  Truth* child = leaves_.data() + (slot + 1) * leaf_stride_;

  // Candidates for slot > 0: modules present at t adjacent to any filled slot, not yet bound.
  if (slot > 0) {
    std::vector<uint32_t>& cands = candidates_[slot];
    cands.clear();
    if (++generation_ == 0) {
      std::fill(mark_.begin(), mark_.end(), 0);
      generation_ = 1;
    }
    for (uint32_t j = 0; j < slot; ++j) mark_[binding_[j]] = generation_;
    for (uint32_t j = 0; j < slot; ++j) {
      const uint32_t m = binding_[j];
      for (uint32_t e = now_->begin[m]; e < now_->begin[m + 1]; ++e) {
        const uint32_t n = now_->ids[e];
        if (mark_[n] == generation_ || !now_->present[n]) continue;
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
  const Truth* own_truth = own_truth_.data();
  const bool last = slot + 1 == k;
  const bool cull = options_.optimizations.neighbor_culling && !sp.cull_leaves.empty();
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
    if (stats_.stopped) return;
    if (cull && culled(slot, c, parent)) continue;
    binding_[slot] = c;
    ++step_.live_by_filled[slot + 1];
    ++step_.live;
    ++step_.created;
    if (options_.live_budget != 0 && step_.created > options_.live_budget) {
      stats_.stopped = true;
      stats_.stop_reason =
          "more than " + std::to_string(options_.live_budget) + " PatternMatchers at watch step " + std::to_string(t_);
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
        const Truth v = decide(program_.leaves[*l], *l);
        all &= v;
        any |= v;
        if (!last) child[*l] = v;
      }
      result = static_cast<Truth>((all & 1) | (any & 2));
    } else {
      copy_bytes(child, parent, leaf_stride_);
      for (const uint16_t* l = own; l != own_end; ++l) child[*l] = own_truth[*l * modules + c];
      for (const uint16_t* l = carried; l != carried_end; ++l) child[*l] = decide(program_.leaves[*l], *l);
      result = program_.evaluate(child, stack_.data());
    }
    if (last) {
      if (result == kTrue) {
        ++step_.matches;
        if (match_values_ + k + kCopyChunk > matches_.size()) matches_.resize(2 * matches_.size() + 4096);
        copy_ids(matches_.data() + match_values_, binding_.data(), k);
        match_values_ += k;
      }
      continue;
    }
    if (result == kFalse && options_.optimizations.early_termination) continue;
    extend(slot + 1);
  }
}

bool CentralizedDetector::culled(uint32_t slot, uint32_t candidate, const Truth* leaves) {
  std::memcpy(trial_.data(), leaves, trial_.size());
  for (uint16_t l : program_.slots[slot].cull_leaves) {
    const Leaf& leaf = program_.leaves[l];
    trial_[l] = neighbor(binding_[static_cast<size_t>(leaf.x)], leaf.offset, candidate);
  }
  return program_.evaluate(trial_.data(), stack_.data()) == kFalse;
}

}  // namespace dw::watch
