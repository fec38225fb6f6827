// A watchpoint's reading of one group over a recorded window of the history (sim/causal_history.h):
// the Reader of watch/evaluator.h with every slot's "now" at step t, as StepView's reader reads a
// step. `why match` evaluates a match's value code through it, noting every variable it reads
// (docs/design.md §7b, a match's cone); `find` and the window's pinned expressions decide a
// condition on a group at a step through it (sim/group_query.h). Outside the window a read is
// unknown.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <tuple>
#include <utility>
#include <vector>

#include "sim/causal_history.h"
#include "watch/domains.h"
#include "watch/evaluator.h"
#include "watch/frame.h"
#include "watch/program.h"

namespace dw::sim {

class HistoryReader {
 public:
  // `columns`: the model's column of each of the program's variables; `universe`: what id(m) reads.
  HistoryReader(const CausalHistory& h, std::vector<int> columns, const watch::Universe& universe,
                std::span<const ModuleId> group, int64_t t)
      : h_(h), columns_(std::move(columns)), universe_(universe), group_(group), t_(t) {}

  // Every slot's "now" moves to step t.
  void at(int64_t t) { t_ = t; }
  // When set, each variable read is noted in `read`: (module, the model's column, step), id(m) left out.
  bool note_reads = false;
  std::vector<std::tuple<ModuleId, int, int64_t>> read;

  // Module m's variable (the program's index) at `step`: unknown outside the window or while m is absent.
  watch::Value value(ModuleId m, int variable, int64_t step) {
    if (!h_.holds(step) || !h_.present(step, m)) return {};
    if (variable == watch::kIdVariable) return watch::known_value(universe_.id(m));  // no value with a history
    const int column = columns_[size_t(variable)];
    if (column < 0) return {};
    if (note_reads) read.emplace_back(m, column, step);
    return watch::known_value(h_.value(step, m, column));
  }
  // y in N(x, step).
  watch::Truth adjacent(ModuleId x, int64_t step, uint32_t y) const {
    if (!h_.holds(step) || !h_.present(step, x)) return watch::kUnknown;
    const auto ns = h_.at(step).graph->neighbors(x);
    return watch::truth_of(std::find(ns.begin(), ns.end(), y) != ns.end());
  }

  // The Reader of watch/evaluator.h.
  watch::Value term(const watch::ValueInstr& in) { return value(group_[size_t(in.slot)], in.variable, t_ + in.offset); }
  int open(const watch::AggregateCode& a) {
    step_ = t_ + a.offset;
    if (!h_.holds(step_)) {
      elements_.clear();
      return -1;
    }
    const StepRecord& rec = h_.at(step_);
    return watch::open_domain(
        a.domain, a.hops, [&] { return group_[size_t(a.slot)]; }, 0, h_.modules,
        [&](uint32_t u, auto&& visit) {
          for (ModuleId w : rec.graph->neighbors(u)) visit(w);
        },
        [&](uint32_t u) { return rec.present[u] != 0; }, [&](uint32_t, auto&& gather) { gather(elements_); }, elements_,
        seen_);
  }
  watch::Value bound(int i, const watch::ValueInstr& in) { return value(bound_id(i), in.variable, step_ + in.offset); }
  uint32_t bound_id(int i) const { return elements_[size_t(i)]; }
  watch::Truth bound_adjacent(int i, int offset, uint32_t y) const { return adjacent(bound_id(i), step_ + offset, y); }
  int expand(int i) {
    const StepRecord& rec = h_.at(step_);
    return watch::add_candidates(
        elements_[size_t(i)],
        [&](uint32_t u, auto&& visit) {
          for (ModuleId w : rec.graph->neighbors(u)) visit(w);
        },
        [&](uint32_t u) { return rec.present[u] != 0; }, elements_, seen_);
  }
  int keep(const std::vector<uint8_t>& joined) { return watch::keep_members(elements_, joined); }
  uint32_t slot_module(int slot) const { return group_[size_t(slot)]; }
  watch::Truth slot_adjacent(const watch::ConditionTest& c, uint32_t y) const {
    return adjacent(group_[size_t(c.x)], t_ + c.offset, y);
  }
  int64_t now(int) const { return t_; }

 private:
  const CausalHistory& h_;
  std::vector<int> columns_;
  const watch::Universe& universe_;
  std::span<const ModuleId> group_;
  int64_t t_;
  int64_t step_ = 0;  // the open aggregate's
  std::vector<uint32_t> elements_;
  watch::VisitMarks seen_;
};

}  // namespace dw::sim
