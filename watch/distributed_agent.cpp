#include "watch/distributed_agent.h"

#include <algorithm>
#include <cstring>

namespace dw::watch {
namespace {

// The scratch record is sent with chunked copies (copy_ids) that may read past its end.
constexpr size_t kScratchSlack = 16;

Truth membership(const uint32_t* ids, uint32_t count, uint32_t m) {
  if (count == kUnknownSet) return kUnknown;
  return truth_of(std::find(ids, ids + count, m) != ids + count);
}

}  // namespace

AgentContext::AgentContext(const Program& p, const Optimizations& o, uint64_t budget)
    : program(p), layout(p), optimizations(o), live_limit(budget ? budget : UINT64_MAX) {
  stack.resize(static_cast<size_t>(p.max_stack));
  trial.resize(p.leaves.size());
  for (size_t slot = 0; slot < p.slots.size(); ++slot)
    if (!p.slots[slot].sets.empty()) slot_appends_sets |= 1u << slot;
}

void DistributedAgent::prepare(int64_t f, const Program& p) {
  prepared_step_ = f;
  prepared_slots_ = 0;
  neighbors_now_ = history_.neighbors(f);
  if (p.leaf_count > kInlineLeaves) own_overflow_.resize(p.leaf_count);
}

// Own leaves are decided the first time this step that the module fills their slot.
void DistributedAgent::prepare_slot(int64_t f, const Program& p, uint32_t slot) {
  prepared_slots_ |= 1u << slot;
  for (uint16_t l : p.slots[slot].own_leaves)
    (l < kInlineLeaves ? own_inline_[l] : own_overflow_[l]) = decide(p.leaves[l], f, nullptr);
}

// Decides every leaf that filling `sp`'s slot decides, records them in the PatternMatcher and
// returns the expression's truth so far.
[[gnu::always_inline]] inline Truth DistributedAgent::decide_leaves(const Program& p, const SlotProgram& sp, int64_t f,
                                                                    PatternMatcherRef& pm, AgentContext& ctx) const {
  Truth* leaves = pm.leaves();
  // Plain pointers: stores through Truth* (a char type) could alias a vector's own fields.
  const uint16_t* own = sp.own_leaves.data();
  const uint16_t* own_end = own + sp.own_leaves.size();
  const uint16_t* carried = sp.carried_leaves.data();
  const uint16_t* carried_end = carried + sp.carried_leaves.size();
  if (p.shape == Program::Shape::Conjunction) {
    Truth partial = leaves[0];
    for (const uint16_t* l = own; l != own_end; ++l) partial = kleene_and(partial, own_truth(*l));
    for (const uint16_t* l = carried; l != carried_end; ++l)
      partial = kleene_and(partial, decide(p.leaves[*l], f, &pm));
    leaves[0] = partial;
    return partial;  // and-ed with the pending leaves' U this is F exactly when partial is F
  }
  for (const uint16_t* l = own; l != own_end; ++l) leaves[*l] = own_truth(*l);
  for (const uint16_t* l = carried; l != carried_end; ++l) leaves[*l] = decide(p.leaves[*l], f, &pm);
  return p.evaluate(leaves, ctx.stack.data());
}

// Fills a slot that is not the last and spreads the PatternMatcher to the neighbours. Kept out of
// line so that the common last-slot path stays small.
[[gnu::noinline]] void DistributedAgent::fill_and_spread(int64_t f, PatternMatcherRef pm, AgentContext& ctx,
                                                         PatternMatcherOutbox& out) {
  const Program& p = ctx.program;
  StepStats& st = ctx.step;
  const uint32_t slot = pm.filled();
  const uint32_t filled = slot + 1;
  const SlotProgram& sp = p.slots[slot];
  pm.set_id(slot, self_);
  for (uint16_t c : sp.cells) {
    const CarriedCell& cell = p.cells[c];
    int64_t v = 0;
    const bool known = history_.value(cell.variable, f + cell.offset, v);
    pm.set_cell(c, v, known);
  }
  for (uint16_t s : sp.sets) {
    const std::vector<uint32_t>* n = history_.neighbors(f + p.sets[s].offset);
    const uint32_t count = n == nullptr ? kUnknownSet : static_cast<uint32_t>(n->size());
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
    if (n != nullptr && count != 0) std::memcpy(ctx.scratch.data() + at + 4, n->data(), 4 * count);
    pm.set_bytes(grown);
  }
  const Truth result = decide_leaves(p, sp, f, pm, ctx);
  pm.set_filled(filled);
  if (result == kFalse && ctx.optimizations.early_termination) return;

  // Spread to every neighbour not already in the chain (and not culled).
  uint32_t ids[kMaxSlots];
  for (uint32_t s = 0; s < filled; ++s) ids[s] = pm.id(s);
  const std::vector<uint32_t>& nbrs = *neighbors_now_;
  if (ctx.targets.size() < nbrs.size()) ctx.targets.resize(nbrs.size());
  uint32_t* targets = ctx.targets.data();
  size_t count = 0;
  const bool cull = ctx.optimizations.neighbor_culling && !p.slots[filled].cull_leaves.empty();
  for (uint32_t n : nbrs) {
    if (std::find(ids, ids + filled, n) != ids + filled) continue;
    if (cull && culled(n, pm, ctx)) continue;
    targets[count++] = n;
  }
  const uint64_t used = st.messages + st.live;
  const uint64_t room = ctx.live_limit > used ? ctx.live_limit - used : 0;
  if (count > room) {
    count = room;
    ctx.over_budget = true;
  }
  if (count == 0) return;
  const uint32_t bytes = pm.bytes();
  out.send(self_, {targets, count}, pm.data(), bytes);
  st.messages += count;
  st.bytes += count * bytes;
}

// Inlined into start() and receive(): it is the whole per-PatternMatcher cost.
[[gnu::always_inline]] inline void DistributedAgent::fill_and_forward(int64_t f, PatternMatcherRef pm,
                                                                      AgentContext& ctx, PatternMatcherOutbox& out) {
  const Program& p = ctx.program;
  StepStats& st = ctx.step;
  // The budget counts what is alive and what was sent this step, as in fill_and_spread.
  if (st.live + st.messages >= ctx.live_limit) {
    ctx.over_budget = true;
    return;
  }
  if (prepared_step_ != f) prepare(f, p);
  const uint32_t slot = pm.filled();
  const uint32_t filled = slot + 1;
  const SlotProgram& sp = p.slots[slot];
  if (!(prepared_slots_ & (1u << slot))) prepare_slot(f, p, slot);
  ++st.live_by_filled[filled];
  ++st.live;

  if (filled == static_cast<uint32_t>(p.slot_count())) {
    // The last slot: decide and report; the record itself goes nowhere, so it is not updated.
    // (No later slot reads this one, so it writes no cells or sets.)
    if (decide_leaves(p, sp, f, pm, ctx) != kTrue) return;
    ++st.matches;
    if (ctx.match_values + filled + kCopyChunk > ctx.matches.size()) ctx.matches.resize(2 * ctx.matches.size() + 4096);
    uint32_t* match = ctx.matches.data() + ctx.match_values;
    // Copied from the record, which was written long ago: reading the ids just written one by
    // one as a wide load would stall on store forwarding.
    copy_ids(match, reinterpret_cast<const uint32_t*>(pm.data() + ctx.layout.ids), slot);
    match[slot] = self_;
    ctx.match_values += filled;
    return;
  }

  fill_and_spread(f, pm, ctx, out);
}

void DistributedAgent::start(int64_t f, AgentContext& ctx, PatternMatcherOutbox& out) {
  ctx.scratch.resize(std::max<size_t>(ctx.scratch.size(), ctx.layout.sets + kScratchSlack));
  PatternMatcherRef pm(ctx.scratch.data(), ctx.layout);
  pm.init();
  ++ctx.step.created;
  fill_and_forward(f, pm, ctx, out);
}

void DistributedAgent::receive(int64_t f, std::byte* incoming, AgentContext& ctx, PatternMatcherOutbox& out) {
  if (prepared_step_ != f) prepare(f, ctx.program);
  // Sent to a neighbour at f - 1; a module that has left by f never fills it.
  if (neighbors_now_ == nullptr) return;
  PatternMatcherRef pm(incoming, ctx.layout);
  if (ctx.slot_appends_sets & (1u << pm.filled())) {
    // This slot appends neighbour sets: fill a copy with room to grow.
    const uint32_t bytes = pm.bytes();
    if (ctx.scratch.size() < bytes + kScratchSlack) ctx.scratch.resize(bytes + kScratchSlack);
    std::memcpy(ctx.scratch.data(), incoming, bytes);
    pm = PatternMatcherRef(ctx.scratch.data(), ctx.layout);
  }
  fill_and_forward(f, pm, ctx, out);
}

// `pm` is null for own leaves, which read nothing carried.
Truth DistributedAgent::decide(const Leaf& leaf, int64_t f, const PatternMatcherRef* pm) const {
  if (leaf.kind == LeafKind::Neighbor) {
    if (leaf.set >= 0) {  // x filled earlier and carried N(x): am I in it?
      uint32_t count;
      const uint32_t* ids = pm->set(static_cast<uint32_t>(leaf.set), count);
      return membership(ids, count, self_);
    }
    // I am x: is y, filled earlier, in my own neighbour set at the offset?
    const std::vector<uint32_t>* mine = history_.neighbors(f + leaf.offset);
    if (mine == nullptr) return kUnknown;
    return truth_of(std::find(mine->begin(), mine->end(), pm->id(static_cast<uint32_t>(leaf.y))) != mine->end());
  }
  auto operand = [&](const TermRef& t, int64_t& v) {
    return t.cell >= 0 ? pm->cell(static_cast<uint32_t>(t.cell), v) : history_.value(t.variable, f + t.offset, v);
  };
  int64_t a, b = leaf.constant;
  if (!operand(leaf.lhs, a)) return kUnknown;
  if (!leaf.rhs_is_constant && !operand(leaf.rhs, b)) return kUnknown;
  return truth_of(holds(leaf.op, a, b));
}

// Neighbour culling (paper §IV-C): would the expression be false whatever else fills, if
// `candidate` took the next slot? Only neighbor(x next) terms with x already filled can tell.
bool DistributedAgent::culled(uint32_t candidate, const PatternMatcherRef& pm, AgentContext& ctx) const {
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
