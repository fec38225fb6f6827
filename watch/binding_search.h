// The search at the heart of the centralized reading (paper Alg. 1, docs/design.md §4 and §4a): every
// binding of one watch step whose slots form the group shape and make the expression true. Depth
// first over the slots in order, so memory stays bounded by the watchpoint's size, with the
// paper's early termination and neighbour culling. The centralized detector runs it over the
// whole ensemble; for `any` groups it assigns the slots within one connected group, which is also
// what a simultaneous-state PatternMatcher does at the module that completes its group.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "watch/chunked_copy.h"
#include "watch/detector.h"
#include "watch/step_view.h"

namespace dw::watch {

// Matches of one watch step: slot_count dense ids each, the first `values` of `ids` (grown in
// chunks, so that adding one is a plain chunked copy).
struct MatchBuffer {
  std::vector<uint32_t> ids;
  size_t values = 0;
  // Adds the binding `first` (k - 1 ids) then `last`. The last id is written on its own: copying
  // it from where it was just stored would stall on store forwarding.
  void add(const uint32_t* first, uint32_t k, uint32_t last) {
    if (values + k + kCopyChunk > ids.size()) grow();
    uint32_t* match = ids.data() + values;
    copy_ids(match, first, k - 1);
    match[k - 1] = last;
    values += k;
  }
  void grow() { ids.resize(2 * ids.size() + 4096); }
};

// The values of the actions (docs/design.md §4b) of every match in `ids` (slot_count ids each), read
// through the view the matches were found in, into `out` (cleared first).
void action_values(const StepView& view, const Program& program, std::span<const uint32_t> ids,
                   std::vector<Value>& out);

class BindingSearch {
 public:
  BindingSearch(const Program& program, const Optimizations& optimizations, uint64_t live_budget, uint32_t modules);

  // Chain or Ordered bindings with slot 0 from `first`, each later slot a neighbour at t of the
  // slot before (Chain) or of any earlier slot (Ordered).
  void search(const StepView& view, GroupShape shape, std::span<const uint32_t> first, StepStats& stats,
              MatchBuffer& out);
  // Every assignment of the slots to the modules of `group` (as many as slots). The view must be
  // resolved with its fillable slots.
  void assign(const StepView& view, std::span<const uint32_t> group, StepStats& stats, MatchBuffer& out);

  bool stopped() const { return !stop_reason_.empty(); }
  // Stops the search from outside (the groups it is given went past the budget).
  void stop(std::string reason) { stop_reason_ = std::move(reason); }
  const std::string& stop_reason() const { return stop_reason_; }

 private:
  // A conjunction's leaves decided so far, folded: and of their "may be true" bits, or of their
  // "may be false" bits.
  struct Fold {
    Truth all = 1, any = 0;
  };
  // One slot of the search: what every candidate for it shares.
  struct Level {
    uint32_t slot = 0;
    const SlotProgram* program = nullptr;
    const Truth* parent = nullptr;
    Truth* child = nullptr;
    bool last = false, cull = false, conjunction = false;
    bool own_last = false;  // the last slot of a conjunction, decided by own leaves alone (finish_own)
    Fold decided;
  };
  Level level(uint32_t slot, Fold decided) const;
  bool take(const Level& level, uint32_t candidate, Fold& decided);
  void extend(uint32_t slot, Fold decided);
  void finish_own(uint32_t slot, Fold decided);
  void assign_slot(uint32_t slot, uint32_t unbound, Fold decided);
  void assign_own(uint32_t slot, uint32_t unbound, bool satisfied);
  bool completable(uint32_t slot, uint32_t left) const;
  bool culled(uint32_t slot, uint32_t candidate, const Truth* leaves);
  void next_generation();
  void over_budget();

  const Program& program_;
  Optimizations optimizations_;
  uint64_t live_budget_;
  uint32_t modules_;
  std::string stop_reason_;

  // The search under way.
  const StepView* view_ = nullptr;
  GroupShape shape_ = GroupShape::Ordered;
  std::span<const uint32_t> group_;
  StepStats* stats_ = nullptr;
  MatchBuffer* out_ = nullptr;
  std::vector<uint32_t> binding_;
  uint32_t leaf_stride_ = 0;    // leaves per level, rounded up for chunked copies
  std::vector<Truth> leaves_;   // (k + 1) levels of leaf values
  std::vector<Truth> pending_;  // [slot]: kFalse when a later slot decides some leaf, else 0
  std::vector<Truth> stack_, trial_;
  std::vector<std::vector<uint32_t>> candidates_;  // per slot
  std::vector<uint32_t> mark_;
  std::vector<Level> levels_;  // per slot: what does not change (level() adds the rest)
  uint32_t takers_[32] = {};
  uint32_t satisfiers_[32] = {};  // any: per slot, the members whose own leaves there are all true
  // A conjunction of own leaves only (each reads one slot's module): a binding matches exactly
  // when every slot's own leaves are true, so assign_own needs no leaf values.
  bool own_conjunction_ = false;
  uint32_t slot_count_ = 0;  // any: per slot, the group's members (bits) that may take it
  uint32_t generation_ = 0;
};

}  // namespace dw::watch
