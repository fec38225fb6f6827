#include "watch/distributed_agents.h"

#include <algorithm>
#include <cstring>

#include "watch/distributed_reader.h"
#include "watch/kept_windows.h"

namespace dw::watch {
namespace {

// The scratch record is sent with chunked copies (copy_ids) that may read past its end.
constexpr size_t kScratchSlack = 16;

// A PatternMatcher with `filled` slots is alive at this step, unless that would pass the budget:
// what is alive and what was sent this step, as in fill_and_spread.
bool admit(AgentContext& ctx, uint32_t filled) {
  StepStats& st = ctx.step;
  if (st.live + st.messages >= ctx.live_limit) {
    ctx.over_budget = true;
    return false;
  }
  ++st.live_by_filled[filled];
  ++st.live;
  return true;
}

}  // namespace

AgentContext::AgentContext(const Program& p, const Optimizations& o, uint64_t budget)
    : program(p),
      layout(p),
      optimizations(o),
      slot_count(static_cast<uint32_t>(p.slot_count())),
      live_limit(budget ? budget : UINT64_MAX),
      evaluation(p) {
  stack.resize(static_cast<size_t>(p.max_stack));
  trial.resize(p.leaves.size());
  scratch.resize(layout.sets + kScratchSlack);
}

DistributedAgents::DistributedAgents(const Program& p, bool temporal_spans, uint32_t first, uint32_t modules)
    : stride_(p.shape == Program::Shape::Conjunction ? static_cast<uint32_t>(p.slot_count())
                                                     : static_cast<uint32_t>(p.leaves.size())),
      first_(first),
      own_(size_t{modules} * stride_, kUnknown) {
  history_.configure(p, temporal_spans, first, modules);
  own_balls_.resize(p.aggregates.size());
  for (const AggregateCode& a : p.aggregates)
    if (a.domain == Domain::Within) own_balls_[static_cast<size_t>(&a - p.aggregates.data())].reserve(modules);
}

void DistributedAgents::record(const Frame& frame, uint32_t begin, uint32_t end, const Program& p,
                               std::span<const int> columns) {
  record_history(frame, begin, end, columns);
  work_out(p, frame.step, begin, end);
}

void DistributedAgents::work_out(const Program& p, int64_t step, uint32_t begin, uint32_t end) {
  work_out_kept_windows(p, step, begin, end);
  const int64_t f = step - p.agent_delay();
  if (f >= 0) prepare(p, f, begin, end);
}

void DistributedAgents::prepare(const Program& p, int64_t f, uint32_t begin, uint32_t end) {
  // Every truth starts true and has its leaves and-ed in: a conjunction's truth per slot all the
  // slot's own leaves, any other shape's truth per leaf just that leaf.
  const bool conjunction = p.shape == Program::Shape::Conjunction;
  std::fill(own_.data() + size_t{begin - first_} * stride_, own_.data() + size_t{end - first_} * stride_, kTrue);
  for (uint32_t slot = 0; slot < p.slots.size(); ++slot)
    for (uint16_t l : p.slots[slot].own_leaves) {
      const uint32_t at = conjunction ? slot : l;
      if (p.leaves[l].kind == LeafKind::Expression) decide_own_expression(p, p.leaves[l], f, begin, end, at);
      else decide_own(p.leaves[l], f, begin, end, at);
    }
  // The PatternMatchers arriving next read the modules' neighbour lists in no order a prefetcher
  // could follow; fetched now, in order, they are in cache by then.
  if (const AgentHistory::StepGraph g = history_.graph(f); g.ids != nullptr)
    for (const uint32_t* n = g.ids + g.begin[begin]; n < g.ids + g.begin[end]; n += 64 / sizeof(uint32_t))
      __builtin_prefetch(n);
}

// Modules [begin, end) work out each kept window's columns at the newest step its conditions can be
// read for, from their own history (watch/kept_windows.h).
void DistributedAgents::work_out_kept_windows(const Program& p, int64_t newest, uint32_t begin, uint32_t end) {
  if (p.kept_windows.empty()) return;
  EvaluatorScratch scratch(p);  // per call: several threads record blocks at once
  std::vector<Truth> phi, psi;
  const size_t from = begin - first_, n = end - begin;  // the history's arrays start at first_
  auto column_of = [&](int variable, int64_t step, const int64_t*& values, const uint8_t*& known) {
    if (!history_.column(variable, step, values, known)) return false;
    values += from;
    known += from;
    return true;
  };
  auto read = [&](size_t m, int variable, int64_t step, int64_t& out) {
    return read_value(begin + static_cast<uint32_t>(m), variable, step, out);
  };
  for (const KeptWindow& w : p.kept_windows) {
    const int64_t s = newest - w.ahead;
    KeptColumns c;
    if (s < 0 || !history_.row(w.column, s, c.now[0], c.now_known[0])) continue;
    for (int i = 0; i < w.columns(); ++i) {
      history_.row(w.column + i, s, c.now[size_t(i)], c.now_known[size_t(i)]);
      c.now[size_t(i)] += from;
      c.now_known[size_t(i)] += from;
      column_of(w.column + i, s - 1, c.before[size_t(i)], c.before_known[size_t(i)]);
    }
    if (w.kind == WindowKind::Times) column_of(w.column + 1, s - w.k - 1, c.count_left, c.count_left_known);
    condition_truths(p, w.phi, s, n, column_of, read, scratch, phi);
    if (w.kind == WindowKind::Since) condition_truths(p, w.psi, s, n, column_of, read, scratch, psi);
    advance_window(w, s, phi.data(), psi.data(), c, n);
  }
}

// And-s own leaf `leaf` of modules [begin, end) at detector step f into own_[m * stride_ + at], a
// column at a time. Absent modules get a truth too, which nothing reads.
void DistributedAgents::decide_own(const Leaf& leaf, int64_t f, uint32_t begin, uint32_t end, uint32_t at) {
  begin -= first_, end -= first_;  // own_ and the history's columns are kept from first_ on
  Truth* own = own_.data() + at;
  const size_t stride = stride_;
  const int64_t *a = nullptr, *b = nullptr;
  const uint8_t *a_known = nullptr, *b_known = nullptr;
  if (!history_.column(leaf.lhs.variable, f + leaf.lhs.offset, a, a_known) ||
      (!leaf.rhs_is_constant && !history_.column(leaf.rhs.variable, f + leaf.rhs.offset, b, b_known))) {
    for (uint32_t m = begin; m < end; ++m) own[m * stride] = kleene_and(own[m * stride], kUnknown);
    return;
  }
  // One loop per operator and right-hand side, so that the loop body has no branches.
  with_compare(leaf.op, [&](auto holds_op) {
    if (b == nullptr) {
      const int64_t c = leaf.constant;
      for (uint32_t m = begin; m < end; ++m)
        own[m * stride] = kleene_and(own[m * stride], a_known[m] ? truth_of(holds_op(a[m], c)) : kUnknown);
    } else {
      for (uint32_t m = begin; m < end; ++m)
        own[m * stride] =
            kleene_and(own[m * stride], a_known[m] & b_known[m] ? truth_of(holds_op(a[m], b[m])) : kUnknown);
    }
  });
}

// decide_own for a leaf of value code (docs/design.md §4b), one module at a time.
void DistributedAgents::decide_own_expression(const Program& p, const Leaf& leaf, int64_t f, uint32_t begin,
                                              uint32_t end, uint32_t at) {
  EvaluatorScratch scratch(p);  // per call, not per agents: several threads record blocks at once
  std::vector<uint32_t> neighbors, rows;
  VisitMarks seen;
  for (uint32_t m = begin; m < end; ++m) {
    Reader r(*this, m, static_cast<uint32_t>(leaf.decide_slot), f, nullptr, neighbors, rows, seen);
    r.use_balls(p, own_balls_, first_);
    Truth& own = own_[size_t{m - first_} * stride_ + at];
    own = kleene_and(own, Evaluator(p, r, scratch).leaf(leaf));
  }
}

// Writes, for the PatternMatcher module m fills at f, the table of aggregate `a` over m's
// neighbours (pattern_matcher.h), so that a later slot can decide it. False past the size limit.
bool DistributedAgents::write_table(uint32_t m, int64_t f, const AggregateCode& a, AgentContext& ctx,
                                    PatternMatcherRef& pm) const {
  std::vector<uint32_t>& words = ctx.rows;
  words.assign(2, 0);
  const int64_t step = f + a.offset;
  const int count = Reader::gather_neighbors(history_, m, step, ctx.neighbors);
  words[0] = count < 0 ? kUnknownSet : static_cast<uint32_t>(count);
  for (int i = 0; i < count; ++i) {
    const uint32_t n = ctx.neighbors[static_cast<size_t>(i)];
    words.push_back(n);
    for (const TermRef& r : a.neighbor_reads) {
      int64_t v = 0;
      const bool known = read_value(n, r.variable, step + r.offset, v);
      const uint64_t bits = static_cast<uint64_t>(v);
      words.insert(words.end(), {static_cast<uint32_t>(bits), static_cast<uint32_t>(bits >> 32), known});
    }
    for (int16_t o : a.neighbor_sets) {
      uint32_t c = 0;
      const uint32_t* ns = history_.neighbors(n, step + o, c);
      words.push_back(ns == nullptr ? kUnknownSet : c);
      if (ns != nullptr) words.insert(words.end(), ns, ns + c);
    }
  }
  words[1] = static_cast<uint32_t>(words.size() - 2);
  const uint32_t at = pm.bytes();
  const uint64_t size = uint64_t{at} + 4 * uint64_t{words.size()};
  if (size > kMaxPatternMatcherBytes) {
    ctx.over_budget = true;
    ctx.stop_reason = "a PatternMatcher would carry more than 16 MiB of neighbour sets";
    return false;
  }
  if (ctx.scratch.size() < size + kScratchSlack) {
    ctx.scratch.resize(size * 2 + kScratchSlack);
    pm = PatternMatcherRef(ctx.scratch.data(), ctx.layout);
  }
  std::memcpy(ctx.scratch.data() + at, words.data(), 4 * words.size());
  pm.set_bytes(static_cast<uint32_t>(size));
  return true;
}

// The values of a match's actions (docs/design.md §4b), read as the match's reading reads them.
void DistributedAgents::act(uint32_t m, int64_t f, const PatternMatcherRef& pm, AgentContext& ctx) const {
  const Program& p = ctx.program;
  Reader r(*this, m, pm.filled(), f, &pm, ctx.neighbors, ctx.rows, ctx.seen);
  Evaluator e(p, r, ctx.evaluation);
  for (const ActionCode& a : p.actions)
    ctx.action_values.push_back(a.value == kNoCode ? known_value(0) : e.value(a.value, 0, -1));
}

// Decides every leaf that filling `slot` decides into `leaves` (the PatternMatcher's, or a copy)
// and returns the expression's truth so far.
[[gnu::always_inline]] inline Truth DistributedAgents::decide_leaves(const SlotProgram& sp, uint32_t slot, uint32_t m,
                                                                     int64_t f, PatternMatcherRef& pm, Truth* leaves,
                                                                     AgentContext& ctx) const {
  const Program& p = ctx.program;
  const Truth* own = own_.data() + size_t{m - first_} * stride_;
  // Plain pointers: stores through Truth* (a char type) could alias a vector's own fields.
  const uint16_t* carried = sp.carried_leaves.data();
  const uint16_t* carried_end = carried + sp.carried_leaves.size();
  if (p.shape == Program::Shape::Conjunction) {
    Truth partial = kleene_and(leaves[0], own[slot]);
    for (const uint16_t* l = carried; l != carried_end; ++l)
      partial = kleene_and(partial, decide(p.leaves[*l], m, f, pm, ctx));
    leaves[0] = partial;
    return partial;  // and-ed with the pending leaves' U this is F exactly when partial is F
  }
  for (uint16_t l : sp.own_leaves) leaves[l] = own[l];
  for (const uint16_t* l = carried; l != carried_end; ++l) leaves[*l] = decide(p.leaves[*l], m, f, pm, ctx);
  return p.evaluate(leaves, ctx.stack.data());
}

// The last slot: decide and report. The record itself goes nowhere, so it is read, not written
// (other receivers read it too). No later slot reads this one, so it writes no cells or sets.
[[gnu::always_inline]] inline void DistributedAgents::finish(uint32_t m, int64_t f, PatternMatcherRef pm,
                                                             AgentContext& ctx) const {
  const uint32_t slot = pm.filled();
  Truth conjunction = pm.leaves()[0];
  Truth* leaves = &conjunction;
  if (ctx.program.shape != Program::Shape::Conjunction) {
    std::memcpy(ctx.trial.data(), pm.leaves(), ctx.trial.size());
    leaves = ctx.trial.data();
  }
  if (decide_leaves(ctx.program.slots[slot], slot, m, f, pm, leaves, ctx) != kTrue) return;
  ++ctx.step.matches;
  if (ctx.match_values + slot + 1 + kCopyChunk > ctx.matches.size()) ctx.matches.resize(2 * ctx.matches.size() + 4096);
  uint32_t* match = ctx.matches.data() + ctx.match_values;
  copy_ids(match, reinterpret_cast<const uint32_t*>(pm.data() + ctx.layout.ids), slot);
  match[slot] = m;
  ctx.match_values += slot + 1;
  if (!ctx.program.actions.empty()) act(m, f, pm, ctx);
}

// Fills a slot that is not the last (in the context's scratch record) and spreads the
// PatternMatcher to the neighbours.
void DistributedAgents::fill_and_spread(uint32_t m, int64_t f, PatternMatcherRef pm, AgentContext& ctx,
                                        PatternMatcherOutbox& out) {
  const Program& p = ctx.program;
  StepStats& st = ctx.step;
  const uint32_t slot = pm.filled();
  const uint32_t filled = slot + 1;
  const SlotProgram& sp = p.slots[slot];
  pm.set_id(slot, m);
  for (uint16_t c : sp.cells) {
    const CarriedCell& cell = p.cells[c];
    int64_t v = 0;
    const bool known = read_value(m, cell.variable, f + cell.offset, v);
    pm.set_cell(c, v, known);
  }
  for (uint16_t s : sp.sets) {
    if (p.sets[s].aggregate >= 0) {
      if (!write_table(m, f, p.aggregates[static_cast<size_t>(p.sets[s].aggregate)], ctx, pm)) return;
      continue;
    }
    uint32_t count = 0;
    const uint32_t* n = history_.neighbors(m, f + p.sets[s].offset, count);
    if (n == nullptr) count = kUnknownSet;
    const uint32_t at = pm.bytes();
    const uint64_t size = uint64_t{at} + 4 + (n == nullptr ? 0 : 4 * uint64_t{count});
    if (size > kMaxPatternMatcherBytes) {
      ctx.over_budget = true;
      ctx.stop_reason = "a PatternMatcher would carry more than 16 MiB of neighbour sets";
      return;
    }
    const uint32_t grown = static_cast<uint32_t>(size);
    if (ctx.scratch.size() < grown + kScratchSlack) {
      ctx.scratch.resize(grown * 2 + kScratchSlack);
      pm = PatternMatcherRef(ctx.scratch.data(), ctx.layout);
    }
    std::memcpy(ctx.scratch.data() + at, &count, 4);
    if (n != nullptr && count != 0) std::memcpy(ctx.scratch.data() + at + 4, n, 4 * size_t{count});
    pm.set_bytes(grown);
  }
  const Truth result = decide_leaves(sp, slot, m, f, pm, pm.leaves(), ctx);
  pm.set_filled(filled);
  if (result == kFalse && ctx.optimizations.early_termination) return;

  // Spread to every neighbour not already in the chain (and not culled).
  // The chain's ids padded to fours with an id no module has, so that a test is straight-line
  // compares (one group of four for chains up to four).
  uint32_t ids[kMaxSlots + 3];
  const uint32_t padded = (filled + 3) & ~3u;
  for (uint32_t s = 0; s < padded; ++s) ids[s] = s < filled ? pm.id(s) : UINT32_MAX;
  auto in_chain = [&](uint32_t n) {
    bool found = (ids[0] == n) | (ids[1] == n) | (ids[2] == n) | (ids[3] == n);
    for (uint32_t s = 4; s < padded; s += 4)
      found |= (ids[s] == n) | (ids[s + 1] == n) | (ids[s + 2] == n) | (ids[s + 3] == n);
    return found;
  };
  uint32_t degree = 0;
  const uint32_t* nbrs = history_.neighbors(m, f, degree);                                // m is present at f
  if (ctx.targets.size() < degree + kCopyChunk) ctx.targets.resize(degree + kCopyChunk);  // see copy_ids
  uint32_t* targets = ctx.targets.data();
  size_t count = 0;
  const bool cull = ctx.optimizations.neighbor_culling && !p.slots[filled].cull_leaves.empty();
  if (cull) {
    for (const uint32_t* n = nbrs; n != nbrs + degree; ++n)
      if (!in_chain(*n) && !culled(*n, pm, ctx)) targets[count++] = *n;
  } else {
    for (const uint32_t* n = nbrs; n != nbrs + degree; ++n) {  // without branches: most are taken
      targets[count] = *n;
      count += !in_chain(*n);
    }
  }
  const uint64_t used = st.messages + st.live;
  const uint64_t room = ctx.live_limit > used ? ctx.live_limit - used : 0;
  if (count > room) {
    count = room;
    ctx.over_budget = true;
  }
  if (count == 0) return;
  const uint32_t bytes = pm.bytes();
  out.send(m, {targets, count}, pm.data(), bytes);
  st.messages += count;
  st.bytes += count * bytes;
}

void DistributedAgents::start(uint32_t m, int64_t f, AgentContext& ctx, PatternMatcherOutbox& out) {
  ++ctx.step.created;
  if (!admit(ctx, 1)) return;
  if (ends_here(m, 0, ctx)) return;
  PatternMatcherRef pm(ctx.scratch.data(), ctx.layout);
  pm.init();
  if (ctx.slot_count == 1) finish(m, f, pm, ctx);
  else fill_and_spread(m, f, pm, ctx, out);
}

void DistributedAgents::receive(std::span<const uint32_t> to, int64_t f, const std::byte* incoming, AgentContext& ctx,
                                PatternMatcherOutbox& out) {
  // Sent to neighbours at f - 1; a module that has left by f never fills it.
  const uint8_t* present = history_.presence(f);
  // Only read through this view: the record is shared by all its receivers.
  PatternMatcherRef view(const_cast<std::byte*>(incoming), ctx.layout);
  const uint32_t filled = view.filled() + 1;
  if (filled == ctx.slot_count) {
    finish_all(to, f, present, view, ctx);
    return;
  }
  const uint32_t bytes = view.bytes();
  if (ctx.scratch.size() < bytes + kScratchSlack) ctx.scratch.resize(bytes + kScratchSlack);
  for (uint32_t m : to) {
    if (!present[m - first_]) continue;
    if (!admit(ctx, filled)) return;
    if (ends_here(m, filled - 1, ctx)) continue;
    // Chunked: the lanes keep slack past their last record, the scratch past its end.
    copy_ids(reinterpret_cast<uint32_t*>(ctx.scratch.data()), reinterpret_cast<const uint32_t*>(incoming), bytes / 4);
    fill_and_spread(m, f, PatternMatcherRef(ctx.scratch.data(), ctx.layout), ctx, out);
    if (ctx.over_budget) return;
  }
}

// The last slot for every receiver of one record (all at detector step f, whose presence is
// `present`, from first_ on). A conjunction whose last slot decides only own leaves, the commonest
// case, is one lookup per receiver.
void DistributedAgents::finish_all(std::span<const uint32_t> to, int64_t f, const uint8_t* present,
                                   PatternMatcherRef pm, AgentContext& ctx) const {
  const uint32_t slot = pm.filled();
  const SlotProgram& sp = ctx.program.slots[slot];
  StepStats& st = ctx.step;
  if (ctx.program.shape != Program::Shape::Conjunction || !sp.carried_leaves.empty() || !ctx.program.actions.empty()) {
    for (uint32_t m : to) {
      if (!present[m - first_]) continue;
      if (!admit(ctx, slot + 1)) return;
      finish(m, f, pm, ctx);
    }
    return;
  }
  const uint64_t used = st.live + st.messages;
  const uint64_t room = ctx.live_limit > used ? ctx.live_limit - used : 0;
  if (ctx.match_values + to.size() * (slot + 1) + kCopyChunk > ctx.matches.size())
    ctx.matches.resize(2 * ctx.matches.size() + to.size() * (slot + 1) + 4096);
  const Truth before = pm.leaves()[0];
  const uint32_t* ids = reinterpret_cast<const uint32_t*>(pm.data() + ctx.layout.ids);
  const Truth* own = own_.data() + slot;
  uint32_t* match = ctx.matches.data() + ctx.match_values;
  uint64_t live = 0;
  for (uint32_t m : to) {
    if (!present[m - first_]) continue;
    if (live == room) {
      ctx.over_budget = true;
      break;
    }
    ++live;
    if (kleene_and(before, own[size_t{m - first_} * stride_]) != kTrue) continue;
    copy_ids(match, ids, slot);
    match[slot] = m;
    match += slot + 1;
  }
  const size_t values = static_cast<size_t>(match - ctx.matches.data()) - ctx.match_values;
  ctx.match_values += values;
  st.matches += values / (slot + 1);
  st.live += live;
  st.live_by_filled[slot + 1] += live;
}

// A carried leaf (SlotProgram::carried_leaves), read against the PatternMatcher being filled.
Truth DistributedAgents::decide(const Leaf& leaf, uint32_t m, int64_t f, const PatternMatcherRef& pm,
                                AgentContext& ctx) const {
  if (leaf.kind == LeafKind::Expression) {
    Reader r(*this, m, pm.filled(), f, &pm, ctx.neighbors, ctx.rows, ctx.seen);
    return Evaluator(ctx.program, r, ctx.evaluation).leaf(leaf);
  }
  if (leaf.kind == LeafKind::Neighbor) {
    if (leaf.set >= 0) {  // x filled earlier and carried N(x): am I in it?
      uint32_t count;
      const uint32_t* ids = pm.set(static_cast<uint32_t>(leaf.set), count);
      return membership(ids, count, m);
    }
    // I am x: is y, filled earlier, in my own neighbour set at the offset?
    uint32_t count = 0;
    const uint32_t* mine = history_.neighbors(m, f + leaf.offset, count);
    if (mine == nullptr) return kUnknown;
    const uint32_t y = pm.id(static_cast<uint32_t>(leaf.y));
    return truth_of(std::find(mine, mine + count, y) != mine + count);
  }
  auto operand = [&](const TermRef& t, int64_t& v) {
    return t.cell >= 0 ? pm.cell(static_cast<uint32_t>(t.cell), v) : history_.value(m, t.variable, f + t.offset, v);
  };
  int64_t a, b = leaf.constant;
  if (!operand(leaf.lhs, a)) return kUnknown;
  if (!leaf.rhs_is_constant && !operand(leaf.rhs, b)) return kUnknown;
  return truth_of(holds(leaf.op, a, b));
}

// Neighbour culling (paper §IV-C): would the expression be false whatever else fills, if
// `candidate` took the next slot? Only neighbor(x next) terms with x already filled can tell.
bool DistributedAgents::culled(uint32_t candidate, const PatternMatcherRef& pm, AgentContext& ctx) const {
  const std::vector<uint16_t>& cull = ctx.program.slots[pm.filled()].cull_leaves;
  if (ctx.program.shape == Program::Shape::Conjunction) {
    Truth trial = pm.leaves()[0];
    for (uint16_t l : cull) {
      uint32_t count;
      const uint32_t* ids = pm.set(static_cast<uint32_t>(ctx.program.leaves[l].set), count);
      trial = kleene_and(trial, membership(ids, count, candidate));
    }
    return trial == kFalse;
  }
  std::memcpy(ctx.trial.data(), pm.leaves(), ctx.trial.size());
  for (uint16_t l : cull) {
    uint32_t count;
    const uint32_t* ids = pm.set(static_cast<uint32_t>(ctx.program.leaves[l].set), count);
    ctx.trial[l] = membership(ids, count, candidate);
  }
  return ctx.program.evaluate(ctx.trial.data(), ctx.stack.data()) == kFalse;
}

}  // namespace dw::watch
