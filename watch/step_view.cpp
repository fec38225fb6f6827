#include "watch/step_view.h"

#include <algorithm>

#include "watch/detector.h"
#include "watch/domains.h"
#include "watch/kept_windows.h"

namespace dw::watch {

StepHistory::StepHistory(const Program& p, const Universe& u, bool spans, int64_t later)
    : program_(&p),
      scratch_(p),
      modules_(u.module_count()),
      frame_columns_(variable_columns(p, u)),
      columns_(p.column_count()),
      balls_(p.aggregates.size()) {
  if (p.reads_id) ids_ = u.module_ids;
  for (size_t v = 0; v < columns_.size(); ++v)
    columns_[v].configure(spans ? p.extent_plus - p.variable_min_offset[v] + 1 + later : 0);
  graphs_.configure(spans ? p.extent_plus - p.min_neighbor_offset + 1 + later : 0);
}

void StepHistory::record(const Frame& frame) {
  for (size_t v = 0; v < columns_.size(); ++v) {
    Column& col = columns_[v].write(frame.step);
    col.value.resize(modules_);
    col.known.resize(modules_);
    const int c = v < frame_columns_.size() ? frame_columns_[v] : -1;  // a since's bit: worked out below
    for (uint32_t m = 0; m < modules_; ++m) {
      const size_t at = static_cast<size_t>(m) * frame.variable_count + static_cast<size_t>(c);
      const bool known = c >= 0 && frame.present[m] && frame.has(at);
      col.known[m] = known;
      col.value[m] = known ? frame.values[at] : 0;
    }
  }
  // Compared before the write, which may reuse the step before's entry.
  const Graph* before = graphs_.find(frame.step - 1);
  const bool same = before != nullptr && std::ranges::equal(before->present, frame.present) &&
                    std::ranges::equal(before->begin, frame.nbr_begin) && std::ranges::equal(before->ids, frame.nbrs);
  const uint64_t version = same ? before->version : ++versions_;
  Graph& g = graphs_.write(frame.step);
  g.version = version;
  g.present.assign(frame.present.begin(), frame.present.end());
  g.begin.assign(frame.nbr_begin.begin(), frame.nbr_begin.end());
  g.ids.assign(frame.nbrs.begin(), frame.nbrs.end());
  work_out_kept_windows(frame.step);
}

// Each kept window's columns at the newest step its conditions can be read for (watch/kept_windows.h).
void StepHistory::work_out_kept_windows(int64_t newest) {
  const Program& p = *program_;
  auto column_of = [&](int variable, int64_t step, const int64_t*& values, const uint8_t*& known) {
    const Column* c = column(variable, step);
    if (c == nullptr) return false;
    values = c->value.data();
    known = c->known.data();
    return true;
  };
  auto read = [&](size_t m, int variable, int64_t step, int64_t& out) {
    if (variable == kIdVariable) {
      const Graph* g = graph(step);
      if (g == nullptr || !g->present[m]) return false;
      out = id(static_cast<uint32_t>(m));
      return true;
    }
    const Column* c = column(variable, step);
    if (c == nullptr || !c->known[m]) return false;
    out = c->value[m];
    return true;
  };
  for (const KeptWindow& w : p.kept_windows) {
    const int64_t s = newest - w.ahead;
    KeptColumns c;
    if (columns_[static_cast<size_t>(w.column)].find(s) == nullptr) continue;
    for (int i = 0; i < w.columns(); ++i) {
      Column& now = *columns_[static_cast<size_t>(w.column + i)].find(s);
      c.now[size_t(i)] = now.value.data();
      c.now_known[size_t(i)] = now.known.data();
      column_of(w.column + i, s - 1, c.before[size_t(i)], c.before_known[size_t(i)]);
    }
    if (w.kind == WindowKind::Times) column_of(w.column + 1, s - w.k - 1, c.count_left, c.count_left_known);
    condition_truths(p, w.phi, s, modules_, column_of, read, scratch_, phi_);
    if (w.kind == WindowKind::Since) condition_truths(p, w.psi, s, modules_, column_of, read, scratch_, psi_);
    advance_window(w, s, phi_.data(), psi_.data(), c, modules_);
  }
}

size_t StepHistory::bytes() const {
  size_t n = sizeof(*this);
  for (const auto& ring : columns_)
    for (const Column& c : ring.items()) n += c.value.capacity() * sizeof(int64_t) + c.known.capacity();
  for (const Graph& g : graphs_.items())
    n += g.present.capacity() + (g.begin.capacity() + g.ids.capacity()) * sizeof(uint32_t);
  return n;
}

uint64_t StepHistory::held_values() const {
  uint64_t held = static_cast<uint64_t>(graphs_.held());
  for (const auto& ring : columns_) held += static_cast<uint64_t>(ring.held()) * modules_;
  return held;
}

// Reads a binding's state at watch step t for value code: every slot's "now" is t (docs/design.md §4).
class StepView::Reader {
 public:
  Reader(const StepView& v, const uint32_t* binding) : v_(v), h_(*v.history_), binding_(binding) {}

  Value term(const ValueInstr& in) const { return read(in.variable, v_.t_ + in.offset, binding_[in.slot]); }
  int open(const AggregateCode& a) {
    step_ = v_.t_ + a.offset;
    const StepHistory::Graph* g = h_.graph(step_);
    std::vector<uint32_t>& n = v_.neighbors_;
    if (g == nullptr) {
      n.clear();
      return -1;
    }
    if (a.domain == Domain::Component) graph_ = g;  // expand grows it over this graph
    // The domain over step_'s graph (docs/design.md §4b-§4c); within() through this aggregate's kept balls.
    const auto ball = [&](uint32_t m, auto&& gather) {
      const size_t index = static_cast<size_t>(&a - v_.program_->aggregates.data());
      const std::span<const uint32_t> kept = h_.balls(index).ball(m, g->version, gather, n);
      if (kept.data() != n.data()) n.assign(kept.begin(), kept.end());
    };
    return open_domain(
        a.domain, a.hops, [&] { return binding_[a.slot]; }, 0, static_cast<uint32_t>(g->present.size()),
        [&](uint32_t u, auto&& visit) {
          for (uint32_t w : g->neighbors(u)) visit(w);
        },
        [&](uint32_t u) { return g->present[u] != 0; }, ball, n, v_.seen_);
  }
  Value bound(int i, const ValueInstr& in) const { return read(in.variable, step_ + in.offset, bound_id(i)); }
  uint32_t bound_id(int i) const { return v_.neighbors_[static_cast<size_t>(i)]; }
  bool count_where(const ValueInstr& in, CompareOp op, int64_t c, int count, Value& out) const {
    if (in.variable == kIdVariable) return false;
    const StepHistory::Column* column = h_.column(in.variable, step_ + in.offset);
    int64_t n = 0;
    const std::span<const uint32_t> ids(v_.neighbors_.data(), static_cast<size_t>(count));
    out = column != nullptr && count_holding(ids, 0, column->value.data(), column->known.data(), op, c, n)
              ? known_value(n)
              : Value{};
    if (column == nullptr && count == 0) out = known_value(0);
    return true;
  }
  Truth bound_adjacent(int i, int offset, uint32_t y) const {
    const StepHistory::Graph* g = h_.graph(step_ + offset);
    const uint32_t n = bound_id(i);
    if (g == nullptr || !g->present[n]) return kUnknown;
    const auto ns = g->neighbors(n);
    return truth_of(std::find(ns.begin(), ns.end(), y) != ns.end());
  }
  int expand(int i) {
    const StepHistory::Graph* g = graph_;
    return add_candidates(
        v_.neighbors_[static_cast<size_t>(i)],
        [&](uint32_t u, auto&& visit) {
          for (uint32_t w : g->neighbors(u)) visit(w);
        },
        [&](uint32_t u) { return g->present[u] != 0; }, v_.neighbors_, v_.seen_);
  }
  int keep(const std::vector<uint8_t>& joined) { return keep_members(v_.neighbors_, joined); }
  uint32_t slot_module(int slot) const { return binding_[slot]; }
  Truth slot_adjacent(const ConditionTest& t, uint32_t y) const { return v_.neighbor(binding_[t.x], t.offset, y); }
  int64_t now(int) const { return v_.t_; }  // every slot's, in a simultaneous reading

 private:
  Value read(int variable, int64_t step, uint32_t m) const {
    if (variable == kIdVariable) {
      const StepHistory::Graph* g = h_.graph(step);
      if (g == nullptr || !g->present[m]) return {};
      return known_value(h_.id(m));
    }
    const StepHistory::Column* c = h_.column(variable, step);
    if (c == nullptr || !c->known[m]) return {};
    return known_value(c->value[m]);
  }

  const StepView& v_;
  const StepHistory& h_;
  const uint32_t* binding_;
  int64_t step_ = 0;                           // the open aggregate's
  const StepHistory::Graph* graph_ = nullptr;  // a component's, at step_
};

StepView::StepView(const Program& p, uint32_t modules)
    : program_(&p),
      modules_(modules),
      scratch_(p),
      lhs_(p.leaves.size()),
      rhs_(p.leaves.size()),
      graph_at_offset_(static_cast<size_t>(p.extent_plus - p.min_neighbor_offset) + 1),
      own_truth_(p.leaves.size() * modules) {}

void StepView::resolve(const StepHistory& history, int64_t t, bool slots) {
  const Program& p = *program_;
  t_ = t;
  history_ = &history;
  now_ = history.graph(t);
  // Resolve every term's step once, so that the inner loops only index arrays.
  auto resolve_term = [&](const TermRef& term) {
    ResolvedTerm r;
    if (const StepHistory::Column* c = history.column(term.variable, t + term.offset)) {
      r.value = c->value.data();
      r.known = c->known.data();
    }
    return r;
  };
  for (size_t i = 0; i < p.leaves.size(); ++i) {
    const Leaf& leaf = p.leaves[i];
    if (leaf.kind != LeafKind::Compare) continue;
    lhs_[i] = resolve_term(leaf.lhs);
    rhs_[i] = leaf.rhs_is_constant ? ResolvedTerm{} : resolve_term(leaf.rhs);
  }
  for (size_t o = 0; o < graph_at_offset_.size(); ++o)
    graph_at_offset_[o] = history.graph(t + p.min_neighbor_offset + static_cast<int64_t>(o));
  // A leaf that reads one slot only has the same truth for every binding that puts module m in
  // that slot: decide it once per module.
  uint32_t same[kMaxSlots];
  for (const SlotProgram& sp : p.slots)
    for (uint16_t l : sp.own_leaves) {
      if (p.leaves[l].kind == LeafKind::Compare) {
        for (uint32_t m = 0; m < modules_; ++m) own_truth_[l * modules_ + m] = compare(p.leaves[l], l, m, m);
        continue;
      }
      for (uint32_t m = 0; m < modules_; ++m) {
        std::fill(same, same + p.slot_count(), m);
        own_truth_[l * modules_ + m] = decide(l, same);
      }
    }
  if (p.shape == Program::Shape::Conjunction) {
    own_slot_truth_.assign(p.slots.size() * modules_, kTrue);
    for (uint32_t s = 0; s < p.slots.size(); ++s)
      for (uint16_t l : p.slots[s].own_leaves)
        for (uint32_t m = 0; m < modules_; ++m)
          own_slot_truth_[s * modules_ + m] = kleene_and(own_slot_truth_[s * modules_ + m], own(l, m));
  }
  if (!slots) return;
  fillable_.assign(modules_, 0);
  satisfied_.assign(modules_, 0);
  std::vector<Truth> trial(p.leaves.size()), stack(static_cast<size_t>(p.max_stack));
  for (uint32_t s = 0; s < p.slots.size(); ++s) {
    const SlotProgram& sp = p.slots[s];
    std::fill(trial.begin(), trial.end(), kUnknown);
    for (uint32_t m = 0; m < modules_; ++m) {
      for (uint16_t l : sp.own_leaves) trial[l] = own(l, m);
      if (p.evaluate(trial.data(), stack.data()) != kFalse) fillable_[m] |= 1u << s;
      bool all = true;
      for (uint16_t l : sp.own_leaves) all &= own(l, m) == kTrue;
      if (all) satisfied_[m] |= 1u << s;
    }
  }
}

bool StepView::adjacent(uint32_t from, uint32_t to) const {
  if (now_ == nullptr || !now_->present[from]) return false;
  const auto n = now_->neighbors(from);
  return std::find(n.begin(), n.end(), to) != n.end();
}

Truth StepView::neighbor(uint32_t x, int offset, uint32_t y) const {
  const StepHistory::Graph* g = graph_at_offset_[static_cast<size_t>(offset - program_->min_neighbor_offset)];
  if (g == nullptr || !g->present[x]) return kUnknown;
  const uint32_t* b = g->ids.data() + g->begin[x];
  const uint32_t* e = g->ids.data() + g->begin[x + 1];
  return truth_of(std::find(b, e, y) != e);
}

Truth StepView::compare(const Leaf& leaf, uint32_t i, uint32_t lm, uint32_t rm) const {
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

Truth StepView::decide(uint32_t i, const uint32_t* binding) const {
  const Leaf& leaf = program_->leaves[i];
  if (leaf.kind == LeafKind::Expression) {
    Reader r(*this, binding);
    return Evaluator(*program_, r, scratch_).leaf(leaf);
  }
  if (leaf.kind == LeafKind::Neighbor)
    return neighbor(binding[static_cast<size_t>(leaf.x)], leaf.offset, binding[static_cast<size_t>(leaf.y)]);
  const uint32_t rm = leaf.rhs_is_constant ? 0 : binding[static_cast<size_t>(leaf.rhs.slot)];
  return compare(leaf, i, binding[static_cast<size_t>(leaf.lhs.slot)], rm);
}

}  // namespace dw::watch

namespace dw::watch {

Value StepView::value(uint32_t code, const uint32_t* binding) const {
  Reader r(*this, binding);
  return Evaluator(*program_, r, scratch_).value(code, 0, -1);
}

}  // namespace dw::watch
