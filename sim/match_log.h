// Collects the matches of several detectors and writes them as JSON Lines (docs/design.md §5), sorted by
// t, then by watch (in the order given), then by slot ids in slot order:
//   {"watch":"leaders","t":12,"slots":{"a":4,"b":5,"c":9}}
// A watchpoint with actions (docs/design.md §4b) adds what each asks, its value null when unknown:
//   {"watch":"gradient","t":3,"slots":{"a":4,"b":5},"then":[{"set":"a.dist","module":4,"value":2}]}
// A zero-slot watchpoint's match (docs/design.md §4c) has no slot: {"watch":"w","t":12,"slots":{}}.
// Detectors finish watch steps at different lags; a step is written once every watch is past it.
#pragma once

#include <cstdint>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "watch/detector.h"
#include "watch/watchpoint.h"

namespace dw::sim {

class MatchLog {
 public:
  struct WatchInfo {
    std::string name;
    std::vector<std::string> slots;
    // Per action: the slot it acts on and, for a set, the variable ("" for a remove).
    std::vector<std::pair<int, std::string>> actions = {};
  };

  // What the log needs of a watchpoint: its name, slots and actions.
  static WatchInfo info(const watch::Watchpoint& w);
  // The `then` of one match of a watchpoint with actions: its slots' module ids and its actions'
  // values, as [{"set":"a.dist","module":4,"value":2},{"remove":"b","module":5}].
  static nlohmann::ordered_json then_json(const WatchInfo& w, std::span<const watch::ModuleId> ids,
                                          std::span<const watch::Value> values);

  // The groups of k ids in `ids` (one watch step's matches), sorted by their ids in slot order:
  // the order the log writes them in.
  static std::vector<watch::ModuleId> sorted_groups(std::span<const watch::ModuleId> ids, size_t k);

  // `out` may be null: then matches are only counted. The first `keep` matches of each watch, in
  // written order, are kept for summaries.
  MatchLog(std::vector<WatchInfo> watches, std::ostream* out, size_t keep = 1);

  // The sink to give the detector of watch `index`.
  watch::MatchSink sink(size_t index);
  // Every watch step up to and including `t` is final for every watch: write those.
  void release(int64_t t);
  // The one line of a `count` watchpoint, which keeps no match: {"watch":"w","counted":N}.
  void write_counted(std::string_view watch, uint64_t matches);
  void finish() { release(INT64_MAX); }

  uint64_t count(size_t index) const { return watches_[index].count; }
  struct Kept {
    int64_t t;
    std::vector<watch::ModuleId> ids;
  };
  const std::vector<Kept>& kept(size_t index) const { return watches_[index].kept; }

 private:
  struct Batch {
    int64_t t;
    size_t watch;
    size_t rows;                        // matches (watch::match_rows: a zero-slot one's holds no id)
    std::vector<watch::ModuleId> ids;   // sorted matches, slot_count each
    std::vector<watch::Value> actions;  // in step with ids, action_count each
  };
  struct Watch {
    WatchInfo info;
    std::string prefix;                  // {"watch":"name","t":
    std::vector<std::string> slot_keys;  // "a":
    uint64_t count = 0;
    std::vector<Kept> kept;
  };
  void write(const Batch& b);
  static std::vector<size_t> group_order(std::span<const watch::ModuleId> ids, size_t k);

  std::vector<Watch> watches_;
  std::ostream* out_;
  size_t keep_;
  std::vector<Batch> pending_;
};

}  // namespace dw::sim
