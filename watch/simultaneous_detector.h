// The distributed algorithm in simultaneous-state mode (docs/design.md §4a). Every module starts one
// PatternMatcher per step t0; PatternMatchers travel only between neighbours, one hop per step,
// and every slot reads its module's state and neighbour set at t0 (modules keep that history), so
// the groups found are the centralized ones of the same shape: exactly those while the topology
// holds still, a subset otherwise (a hop whose link is gone by then drops the PatternMatcher and
// counts it as `lost`), never a wrong one.
//
// - chain: each slot is a neighbour of the slot before; a PatternMatcher hops straight on.
// - ordered: slot i + 1 is a neighbour of some filled slot j; the PatternMatcher walks back from
//   slot i to slot j over the tree of hops that filled the slots, then hops on. Each candidate
//   module is reached from the latest slot it neighbours only, so no binding is reached twice.
// - any: the group grows as in ESU (watch/connected_groups.h): from its smallest module, only by
//   exclusive neighbours, walking back to the member that introduced each; the module that
//   completes the group assigns the slots (BindingSearch::assign).
//
// Hosted the way the centralized detector is, over the run's frames; the message passing between
// modules is simulated inside, one hop per detector step. Matches of start step t0 are reported
// once every PatternMatcher of t0 is decided, at detector step t0 + L (watch::hop_latency), and
// at the end of the input it drains over the last step's links (finish).
#pragma once

#include <memory>
#include <vector>

#include "watch/binding_search.h"
#include "watch/connected_groups.h"
#include "watch/detector.h"
#include "watch/step_view.h"
#include "watch/watchpoint.h"

namespace dw::watch {

class SimultaneousDetector final : public Detector {
 public:
  SimultaneousDetector(const Watchpoint& watchpoint, const Universe& universe, DetectorOptions options, MatchSink sink);

  void observe(const Frame& frame) override;
  void finish() override;
  int64_t lag() const override { return watch::lag(*program_, Algorithm::Distributed, options_); }
  std::unique_ptr<Detector> clone() const override;
  Algorithm algorithm() const override { return Algorithm::Distributed; }
  size_t bytes() const override;

 private:
  // A PatternMatcher on its way: at `at`, heading for `target`. Its words in the arena: the
  // members (slot order for chain and ordered, join order for any), the member each was reached
  // from, the leaves decided so far (chain, ordered), then `ext` (module, introducer) pairs: the
  // extension set (any).
  struct Walker {
    int64_t t0 = 0;
    uint32_t at = 0;
    uint32_t target = 0;
    uint32_t data = 0;
    uint16_t ext = 0;
    uint8_t filled = 0;    // members so far
    uint8_t via = 0;       // the member next to target, from which the last hop leaves
    uint8_t position = 0;  // the member it is at while walking back
    bool walking = false;  // at == members[position], not yet at via
  };

  void step(int64_t f, bool start);
  void arrive(const Walker& w, uint32_t* words);
  void start(int64_t t0, uint32_t module);
  void fill_chain(Walker w, uint32_t* words);
  void join_group(Walker w, uint32_t* words);
  void hop(Walker w, const uint32_t* words, uint32_t word_count);
  uint8_t toward(const uint32_t* parents, uint8_t from, uint8_t to) const;
  const StepHistory::Graph* links(int64_t f) const { return history_.graph(std::min(f, newest_)); }
  // What the PatternMatchers of one start step t0 read, and the matches they found.
  struct StartStep {
    StepView view;
    MatchBuffer found;
    UndirectedGraph groups;  // any: N(t0) both ways among present modules, for ESU
    bool symmetric = true;   // any: N(t0) already went both ways
  };
  StartStep& at(int64_t t0) { return starts_[static_cast<size_t>(t0 % static_cast<int64_t>(starts_.size()))]; }
  StepView& view(int64_t t0) { return at(t0).view; }
  void report(int64_t t0);

  // Shared by clones, so that the references the parts below keep stay valid in a snapshot;
  // a snapshot needs nothing else to outlive it.
  std::shared_ptr<const Program> program_;
  DetectorOptions options_;
  GroupShape shape_;
  uint32_t k_;
  int64_t latency_;
  uint32_t leaf_words_;   // leaves packed four to a word
  uint32_t fixed_words_;  // members + parents + leaves
  StepHistory history_;
  int64_t newest_ = -1;            // the newest frame's step
  int64_t next_f_ = 0;             // the next detector step to run
  std::vector<StartStep> starts_;  // per start step in flight, by t0 mod (L + 1)
  BindingSearch search_;
  // PatternMatchers arriving at this step and sent during it.
  std::vector<Walker> arriving_, sent_;
  std::vector<uint32_t> arriving_words_, sent_words_;
  const StepHistory::Graph* links_ = nullptr;  // the links of the step running (links(f))
  std::vector<uint32_t> scratch_, start_words_, mark_, ext_, child_words_;
  std::vector<Truth> stack_, trial_;
  uint32_t generation_ = 0;
  StepStats step_;
  std::vector<Value> actions_;  // the matches reported's actions' values
  std::string stop_reason_;
};

}  // namespace dw::watch
