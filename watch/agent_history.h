// The recent past of every module, as the distributed agents keep it (paper §III-B): the values
// of the variables the watchpoint reads and the modules' neighbour sets, each over exactly the
// steps the watchpoint can still ask for (paper §IV-A), or over the whole run when spans are off.
//
// Laid out by step, not by module, so that recording a step is a few contiguous copies and
// nothing is allocated per module: one ring of rows [module] per program variable, and per step
// the modules' presence and N(m, t) as a CSR graph. A host that lends its graph (Frame::topology)
// has it shared, not copied; a static lattice then costs one graph for the whole history.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "watch/frame.h"
#include "watch/program.h"
#include "watch/step_ring.h"

namespace dw::watch {

class AgentHistory {
 public:
  // Keeps the past of modules [first, first + modules) (all of them in one process; a rank's
  // own, docs/design.md §12). Modules are named by their ids throughout; rows hold only these.
  void configure(const Program& program, bool temporal_spans, uint32_t first, uint32_t modules);

  // Makes room for the frame's step and takes its neighbour graph. Once per step, before the
  // modules are recorded (by one thread: the blocks may then be recorded by several).
  void begin_record(const Frame& frame);
  // Records modules [begin, end) of the frame: presence and the values of the program's
  // variables (`columns`: program variable -> frame column, -1 for none).
  void record(const Frame& frame, uint32_t begin, uint32_t end, std::span<const int> columns);

  // The value of a program variable of module m at `step`; false when unknown (absent, missing,
  // before 0, forgotten).
  bool value(uint32_t m, int variable, int64_t step, int64_t& out) const {
    const Values* row = values_[static_cast<size_t>(variable)].find(step);
    if (row == nullptr || !row->known[m - first_]) return false;
    out = row->values[m - first_];
    return true;
  }

  // Writes module m's value of a program variable at `step` (recorded already): a host's own
  // modules are recorded from frames; a neighbour another rank steps is written here.
  void set_value(uint32_t m, int variable, int64_t step, int64_t value, bool known) {
    Values* row = values_[static_cast<size_t>(variable)].find(step);
    if (row == nullptr) return;
    row->values[m - first_] = known ? value : 0;
    row->known[m - first_] = known;
  }

  // The row of a variable at `step` (recorded already) to write ([m - first()]), or false.
  bool row(int variable, int64_t step, int64_t*& values, uint8_t*& known) {
    Values* row = values_[static_cast<size_t>(variable)].find(step);
    if (row == nullptr) return false;
    values = row->values.data();
    known = row->known.data();
    return true;
  }

  // Every kept module's value of a program variable at `step` ([m - first()], meaningful where
  // known), or false when the step is unknown (before 0, not recorded yet, or forgotten).
  bool column(int variable, int64_t step, const int64_t*& values, const uint8_t*& known) const {
    const Values* row = values_[static_cast<size_t>(variable)].find(step);
    if (row == nullptr) return false;
    values = row->values.data();
    known = row->known.data();
    return true;
  }

  // The CSR neighbour graph at `step` ([module + 1] offsets and the ids), or nulls when unknown.
  struct StepGraph {
    const uint32_t* begin = nullptr;
    const uint32_t* ids = nullptr;
  };
  StepGraph graph(int64_t step) const {
    const Topology* t = topology_.find(step);
    return t != nullptr ? StepGraph{t->begin.data(), t->ids.data()} : StepGraph{};
  }

  // What keeps the graph at `step` alive (the host's own, when it lent it), or null when the step
  // is unknown: the graph's identity, for a host that works something out once per graph.
  std::shared_ptr<const void> graph_owner(int64_t step) const {
    const Topology* t = topology_.find(step);
    return t != nullptr ? t->owner : nullptr;
  }

  // N(m, step), or nullptr when the module was absent then (or the step is unknown); `count` is
  // its size.
  const uint32_t* neighbors(uint32_t m, int64_t step, uint32_t& count) const {
    const Topology* t = topology_.find(step);
    if (t == nullptr || !t->present[m - first_]) return nullptr;
    count = t->begin[m + 1] - t->begin[m];
    // Never null for a present module, even in a graph without a link (whose ids have no storage).
    static constexpr uint32_t kNoLink[1] = {0};
    return t->ids.empty() ? kNoLink : t->ids.data() + t->begin[m];
  }

  bool present(uint32_t m, int64_t step) const {
    const Topology* t = topology_.find(step);
    return t != nullptr && t->present[m - first_];
  }
  // Every kept module's presence at `step` ([m - first()]), or nullptr when the step is unknown.
  const uint8_t* presence(int64_t step) const {
    const Topology* t = topology_.find(step);
    return t != nullptr ? t->present.data() : nullptr;
  }

  uint32_t first() const { return first_; }
  uint32_t modules() const { return modules_; }
  // Values and neighbour ids held now, summed over the modules.
  uint64_t held() const;
  // Heap bytes held (storage allocated, whether filled yet or not); a graph shared with the
  // host is not counted.
  size_t bytes() const;

 private:
  struct Values {
    std::vector<int64_t> values;  // [m - first_]
    std::vector<uint8_t> known;   // [m - first_]
  };
  struct Topology {
    std::vector<uint8_t> present;       // [m - first_]
    std::shared_ptr<const void> owner;  // keeps begin and ids alive
    std::span<const uint32_t> begin;    // [module + 1]
    std::span<const uint32_t> ids;
    bool shared = false;  // owned by the host, not by this history
  };
  struct Graph {  // a graph this history had to copy
    std::vector<uint32_t> begin, ids;
  };

  uint32_t first_ = 0, modules_ = 0;
  std::vector<StepRing<Values>> values_;  // per program variable
  StepRing<Topology> topology_;           // presence and N(m, step)
};

}  // namespace dw::watch
