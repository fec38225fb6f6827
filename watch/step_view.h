// The ensemble's recent steps as a whole-ensemble reading needs them (docs/design.md §4), and one watch
// step t read through them with every slot's "now" at t (simultaneous states). The centralized
// detector reads one step at a time; the simultaneous-state distributed detector holds a view per
// start step in flight.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <span>
#include <vector>

#include "watch/domains.h"
#include "watch/evaluator.h"
#include "watch/frame.h"
#include "watch/kleene.h"
#include "watch/program.h"
#include "watch/step_ring.h"

namespace dw::watch {

class StepHistory {
 public:
  // One variable of every module at one step.
  struct Column {
    std::vector<int64_t> value;
    std::vector<uint8_t> known;
  };
  // Presence and the neighbour graph at one step.
  struct Graph {
    std::vector<uint8_t> present;
    std::vector<uint32_t> begin, ids;
    std::span<const uint32_t> neighbors(uint32_t m) const { return {ids.data() + begin[m], ids.data() + begin[m + 1]}; }
  };

  // Keeps what watch steps up to `later` steps behind the newest frame read (every step without
  // temporal spans).
  StepHistory(const Program& program, const Universe& universe, bool temporal_spans, int64_t later);

  void record(const Frame& frame);
  const Column* column(int variable, int64_t step) const { return columns_[static_cast<size_t>(variable)].find(step); }
  const Graph* graph(int64_t step) const { return graphs_.find(step); }
  size_t bytes() const;
  uint64_t held_values() const;                                         // values and graphs held, in module-steps
  ModuleId id(uint32_t m) const { return ids_.empty() ? m : ids_[m]; }  // what id(m) reads

 private:
  void work_out_kept_windows(int64_t newest);

  const Program* program_;
  EvaluatorScratch scratch_;      // for the kept windows
  std::vector<Truth> phi_, psi_;  // their conditions' truths at a step, per module
  uint32_t modules_;
  std::vector<ModuleId> ids_;       // the universe's, when the program reads id() (empty: each id its index)
  std::vector<int> frame_columns_;  // program variable -> frame column
  // Deques: a StepView keeps pointers to the items across later writes (see StepRing).
  std::vector<StepRing<Column, std::deque<Column>>> columns_;  // per program variable, then kept windows' columns
  StepRing<Graph, std::deque<Graph>> graphs_;
};

class StepView {
 public:
  StepView() = default;
  explicit StepView(const Program& program, uint32_t modules);

  // Reads watch step t: resolves every term to its step's column and decides each module's own
  // leaves (SlotProgram::own_leaves) once; with `slots`, also which slots each module may fill.
  void resolve(const StepHistory& history, int64_t t, bool slots = false);

  int64_t t() const { return t_; }
  const StepHistory::Graph* now() const { return now_; }  // the graph at t, or null
  bool present(uint32_t m) const { return now_ != nullptr && now_->present[m]; }
  bool adjacent(uint32_t from, uint32_t to) const;  // to in N(from, t)

  // A comparison leaf with its left operand read from module lm and its right from rm.
  Truth compare(const Leaf& leaf, uint32_t leaf_index, uint32_t lm, uint32_t rm) const;
  // neighbor(x y) at `offset`: y in N(x, t + offset).
  Truth neighbor(uint32_t x, int offset, uint32_t y) const;
  // A leaf for a binding (module per slot) that fills every slot the leaf reads.
  Truth decide(uint32_t leaf_index, const uint32_t* binding) const;
  // Value code for a binding (an action's value).
  Value value(uint32_t code, const uint32_t* binding) const;
  Truth own(uint32_t leaf_index, uint32_t module) const { return own_truth_[leaf_index * modules_ + module]; }
  const Truth* own_truth() const { return own_truth_.data(); }
  // A conjunction's own leaves of `slot`, and-ed, for every module ([module]): what filling the
  // slot adds to the conjunction from the module's own state.
  const Truth* own_slot_truth(uint32_t slot) const { return own_slot_truth_.data() + size_t{slot} * modules_; }
  // The slots (bit s) where the module's own leaves leave the expression not false: the only
  // slots it can fill in a match. Read with resolve(..., slots = true).
  uint32_t fillable(uint32_t module) const { return fillable_[module]; }
  // The slots (bit s) where every own leaf of the module is true.
  uint32_t satisfied(uint32_t module) const { return satisfied_[module]; }
  size_t bytes() const { return own_truth_.capacity() + own_slot_truth_.capacity() + sizeof(*this); }

 private:
  class Reader;
  struct ResolvedTerm {
    const int64_t* value = nullptr;
    const uint8_t* known = nullptr;
  };
  const Program* program_ = nullptr;
  const StepHistory* history_ = nullptr;
  uint32_t modules_ = 0;
  // Scratch for value code (docs/design.md §4b): an aggregate's neighbours, the evaluator's stacks.
  mutable std::vector<uint32_t> neighbors_;
  mutable VisitMarks seen_;  // within()'s and component()'s search
  mutable EvaluatorScratch scratch_;
  int64_t t_ = -1;
  const StepHistory::Graph* now_ = nullptr;
  std::vector<ResolvedTerm> lhs_, rhs_;                     // per leaf
  std::vector<const StepHistory::Graph*> graph_at_offset_;  // [offset - min_neighbor_offset]
  std::vector<Truth> own_truth_;                            // [leaf * M + module]
  std::vector<Truth> own_slot_truth_;                       // conjunction: [slot * M + module]
  std::vector<uint32_t> fillable_, satisfied_;              // [module]
};

}  // namespace dw::watch
