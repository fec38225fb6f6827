// The watchpoints a session hosts (docs/design.md §7): one slot each, holding the compiled
// watchpoint, its matches over the history and its statistics, so that adding, replacing and
// removing one moves everything it has together. A slot is named by a stable handle, a WatchId
// (its slot's index and that slot's generation, as Box2D's ids): the id of a removed or replaced
// watchpoint names nothing, whatever takes its slot later. The run hosts them in an order, the
// order a State holds their states in (State::watches[w]): a watchpoint's *position*.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "sim/watch_spec.h"
#include "watch/detector.h"

namespace dw::sim {

struct WatchId {
  uint32_t index = UINT32_MAX;  // its slot
  uint32_t generation = 0;      // the slot's when the id was given
  bool operator==(const WatchId&) const = default;
};

// The matches of one watchpoint, in the order found (by t, then by slot ids).
struct MatchList {
  std::vector<int64_t> t;              // the match's watch step
  std::vector<int64_t> detected;       // the step during which it was found (t + the watchpoint's lag)
  std::vector<watch::ModuleId> slots;  // slot_count ids per match
  std::vector<watch::Value> actions;   // a watchpoint with actions: their values, action_count per match
  // A `count` watchpoint keeps no match, only how many it found of each watch step (when found):
  // a few words a step, whatever the number of matches.
  struct Counted {
    int64_t t = 0, detected = 0;
    uint64_t matches = 0;
  };
  std::vector<Counted> counted;
  size_t size() const { return t.size(); }
  // The matches of step t: [first, last) indices (t is sorted, so this is a binary search).
  std::pair<size_t, size_t> at(int64_t step) const;
  // How many matches of watch step t a `count` watchpoint found; of every step.
  uint64_t counted_at(int64_t step) const;
  uint64_t counted_total() const;
  void count(int64_t t, int64_t detected, uint64_t matches) {
    if (matches) counted.push_back({t, detected, matches});
  }
  // Forgets what was found after step `through` (k ids and a actions a match).
  void drop_after(int64_t through, size_t k, size_t a);
};

struct WatchSlot {
  HostedWatchpoint hosted;
  MatchList matches;           // over the history
  watch::DetectorStats stats;  // over the history (the per-step series is the session's own)
  std::vector<int64_t> at;     // the step of each entry of stats.steps
  void add_stats(const watch::StepStats& step, int64_t t) {
    stats.add(step);
    at.push_back(t);
  }
};

class WatchSlots {
 public:
  explicit WatchSlots(std::span<const HostedWatchpoint> initial = {});

  uint32_t size() const { return static_cast<uint32_t>(order_.size()); }
  // The watchpoint at position w.
  WatchSlot& operator[](uint32_t w) { return *slots_[order_[w]]; }
  const WatchSlot& operator[](uint32_t w) const { return *slots_[order_[w]]; }
  WatchId id(uint32_t w) const { return {order_[w], generations_[order_[w]]}; }
  // Where the watchpoint `id` names is, or nothing once it is gone.
  std::optional<uint32_t> position(WatchId id) const;
  // The position of the watchpoint with this name, or nothing.
  std::optional<uint32_t> find(std::string_view name) const;

  // A new watchpoint, last.
  WatchId add(HostedWatchpoint hosted);
  // The last one takes position w's place (w's watchpoint goes, the others keep their positions).
  void move_last_to(uint32_t w);
  // Position w's watchpoint goes; the ones after it move up one.
  void erase(uint32_t w);
  void pop_back() { erase(size() - 1); }

  // The compiled watchpoints in position order, where the slots hold them: what the runtime hosts
  // (valid until a watchpoint is added).
  HostedWatches hosted() const;

 private:
  void free_slot(uint32_t index);

  std::vector<std::optional<WatchSlot>> slots_;  // by id index; a free one holds nothing
  std::vector<uint32_t> generations_;            // by id index: a slot's, one more each time it is freed
  std::vector<uint32_t> free_;                   // free id indices, the last freed last
  std::vector<uint32_t> order_;                  // the id index at each position
};

}  // namespace dw::sim
