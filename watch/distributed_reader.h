// What a module knows as it fills a slot, read by value code in the distributed reading
// (DistributedAgents::Reader, used by watch/distributed_agents.cpp only): its own history, its
// neighbours' values and neighbour sets, what a PatternMatcher carries, and the wider domains of
// docs/design.md §4c from the history the engine keeps of every module.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "watch/distributed_agents.h"
#include "watch/domains.h"

namespace dw::watch {

// Whether m is in a carried set (unknown when the set is).
inline Truth membership(const uint32_t* ids, uint32_t count, uint32_t m) {
  if (count == kUnknownSet) return kUnknown;
  return truth_of(std::find(ids, ids + count, m) != ids + count);
}

// Reads what module m knows as it fills `slot` at detector step f, for value code (docs/design.md §4b):
// its own history; its neighbours' values and neighbour sets, which their messages brought it
// (the hop in Program::agent_delay); and what the PatternMatcher carries of the slots filled
// before (cells, sets, tables). Without a PatternMatcher, only the module's own.
class DistributedAgents::Reader {
 public:
  Reader(const DistributedAgents& agents, uint32_t m, uint32_t slot, int64_t f, const PatternMatcherRef* pm,
         std::vector<uint32_t>& neighbors, std::vector<uint32_t>& rows, VisitMarks& seen)
      : agents_(agents),
        h_(agents.history_),
        m_(m),
        slot_(slot),
        f_(f),
        pm_(pm),
        neighbors_(neighbors),
        rows_(rows),
        seen_(seen) {}

  Value term(const ValueInstr& in) const {
    int64_t v = 0;
    if (in.cell >= 0) return pm_->cell(static_cast<uint32_t>(in.cell), v) ? known_value(v) : Value{};
    return agents_.read_value(m_, in.variable, f_ + in.offset, v) ? known_value(v) : Value{};
  }

  // Slot i fills at t0 + i (docs/design.md §4): its "now", from the one filling now.
  int64_t now(int slot) const { return f_ + slot - static_cast<int64_t>(slot_); }

  int open(const AggregateCode& a) {
    aggregate_ = &a;
    table_ = a.table >= 0;
    if (table_) {
      at_ = pm_->record(static_cast<uint32_t>(a.table));
      const uint32_t count = pm_->word(at_);
      if (count == kUnknownSet) return -1;
      rows_.clear();
      uint32_t w = at_ + 8;
      for (uint32_t i = 0; i < count; ++i) {
        rows_.push_back(w);
        w += 4 + 12 * static_cast<uint32_t>(a.neighbor_reads.size());
        for (size_t s = 0; s < a.neighbor_sets.size(); ++s) {
          const uint32_t n = pm_->word(w);
          w += 4 + (n == kUnknownSet ? 0 : 4 * n);
        }
      }
      return static_cast<int>(count);
    }
    if (a.domain != Domain::Neighbors) return open_wider(a);
    step_ = f_ + a.offset;
    return gather_neighbors(h_, m_, step_, neighbors_);
  }

  // within(), all and component() (docs/design.md §4c): facts of the step's snapshot, read from the history the
  // engine keeps of every module, at the aggregate's own slot's step (all: the match step, slot 0's).
  int open_wider(const AggregateCode& a) {
    step_ = now(a.slot) + a.offset;
    if (h_.presence(step_) == nullptr) {
      neighbors_.clear();
      return -1;
    }
    // within(): kept from step to step when use_balls gave it a cache for this root.
    const auto ball = [&](uint32_t root, auto&& gather) {
      if (balls_ == nullptr || root < ball_first_) {
        gather(neighbors_);
        return;
      }
      BallCache& cache = (*balls_)[static_cast<size_t>(&a - aggregates_)];
      const std::span<const uint32_t> kept =
          cache.ball(root - ball_first_, h_.graph_version(step_), gather, neighbors_);
      if (kept.data() != neighbors_.data()) neighbors_.assign(kept.begin(), kept.end());
    };
    return open_domain(
        a.domain, a.hops, [&] { return slot_module(a.slot); }, h_.first(), h_.first() + h_.modules(),
        [&](uint32_t u, auto&& visit) {
          uint32_t count = 0;
          const uint32_t* ns = h_.neighbors(u, step_, count);
          for (uint32_t i = 0; ns != nullptr && i < count; ++i) visit(ns[i]);
        },
        [&](uint32_t u) { return h_.present(u, step_); }, ball, neighbors_, seen_);
  }

  // within() keeps its balls in `balls` ([aggregate of `p`], roots from `first`) from step to step.
  void use_balls(const Program& p, std::vector<BallCache>& balls, uint32_t first) {
    aggregates_ = p.aggregates.data();
    balls_ = &balls;
    ball_first_ = first;
  }

  bool count_where(const ValueInstr& in, CompareOp op, int64_t c, int count, Value& out) const {
    if (table_ || in.variable == kIdVariable) return false;
    const int64_t* values = nullptr;
    const uint8_t* known = nullptr;
    int64_t n = 0;
    const std::span<const uint32_t> ids(neighbors_.data(), static_cast<size_t>(count));
    if (count == 0) out = known_value(0);
    else if (!h_.column(in.variable, step_ + in.offset, values, known)) out = {};
    else out = count_holding(ids, h_.first(), values, known, op, c, n) ? known_value(n) : Value{};
    return true;
  }

  int expand(int i) {
    return add_candidates(
        neighbors_[static_cast<size_t>(i)],
        [&](uint32_t u, auto&& visit) {
          uint32_t count = 0;
          const uint32_t* ns = h_.neighbors(u, step_, count);
          for (uint32_t j = 0; ns != nullptr && j < count; ++j) visit(ns[j]);
        },
        [&](uint32_t u) { return h_.present(u, step_); }, neighbors_, seen_);
  }
  int keep(const std::vector<uint8_t>& joined) { return keep_members(neighbors_, joined); }

  Value bound(int i, const ValueInstr& in) const {
    if (!table_) {
      int64_t v = 0;
      return agents_.read_value(bound_id(i), in.variable, step_ + in.offset, v) ? known_value(v) : Value{};
    }
    const auto& reads = aggregate_->neighbor_reads;
    uint32_t r = 0;
    while (reads[r].variable != in.variable || reads[r].offset != in.offset) ++r;
    const uint32_t at = rows_[static_cast<size_t>(i)] + 4 + 12 * r;
    if (pm_->word(at + 8) == 0) return {};
    const uint64_t bits = uint64_t{pm_->word(at)} | uint64_t{pm_->word(at + 4)} << 32;
    return known_value(static_cast<int64_t>(bits));
  }

  uint32_t bound_id(int i) const {
    return table_ ? pm_->word(rows_[static_cast<size_t>(i)]) : neighbors_[static_cast<size_t>(i)];
  }

  Truth bound_adjacent(int i, int offset, uint32_t y) const {
    if (!table_) {
      uint32_t count = 0;
      const uint32_t* ns = h_.neighbors(bound_id(i), step_ + offset, count);
      if (ns == nullptr) return kUnknown;
      return truth_of(std::find(ns, ns + count, y) != ns + count);
    }
    uint32_t at = rows_[static_cast<size_t>(i)] + 4 + 12 * static_cast<uint32_t>(aggregate_->neighbor_reads.size());
    for (int16_t o : aggregate_->neighbor_sets) {
      const uint32_t n = pm_->word(at);
      if (o == offset) {
        if (n == kUnknownSet) return kUnknown;
        for (uint32_t j = 0; j < n; ++j)
          if (pm_->word(at + 4 + 4 * j) == y) return kTrue;
        return kFalse;
      }
      at += 4 + (n == kUnknownSet ? 0 : 4 * n);
    }
    return kUnknown;
  }

  uint32_t slot_module(int slot) const { return static_cast<uint32_t>(slot) == slot_ ? m_ : pm_->id(slot); }

  Truth slot_adjacent(const ConditionTest& t, uint32_t y) const {
    if (t.set >= 0) {
      uint32_t count;
      const uint32_t* ids = pm_->set(static_cast<uint32_t>(t.set), count);
      return membership(ids, count, y);
    }
    uint32_t count = 0;
    const uint32_t* ns = h_.neighbors(m_, f_ + t.offset, count);
    if (ns == nullptr) return kUnknown;
    return truth_of(std::find(ns, ns + count, y) != ns + count);
  }

  // N(m, step) as a set of the neighbours present then (docs/design.md §4b), or -1 when m was absent.
  static int gather_neighbors(const AgentHistory& h, uint32_t m, int64_t step, std::vector<uint32_t>& out) {
    uint32_t count = 0;
    const uint32_t* ns = h.neighbors(m, step, count);
    if (ns == nullptr) return -1;
    out.clear();
    for (uint32_t i = 0; i < count; ++i)
      if (h.present(ns[i], step)) out.push_back(ns[i]);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return static_cast<int>(out.size());
  }

 private:
  const DistributedAgents& agents_;
  const AgentHistory& h_;
  uint32_t m_, slot_;
  int64_t f_;
  const PatternMatcherRef* pm_;
  std::vector<uint32_t>& neighbors_;
  std::vector<uint32_t>& rows_;                // table: each row's byte offset in the record
  VisitMarks& seen_;                           // within()'s and component()'s search
  const AggregateCode* aggregates_ = nullptr;  // see use_balls
  std::vector<BallCache>* balls_ = nullptr;
  uint32_t ball_first_ = 0;
  const AggregateCode* aggregate_ = nullptr;
  bool table_ = false;
  uint32_t at_ = 0;
  int64_t step_ = 0;
};

}  // namespace dw::watch
