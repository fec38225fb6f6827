// Static analysis of a parsed watchpoint (paper §IV-A, DESIGN §3): the temporal offset of every
// term, each variable's temporal span, the temporal extent E+, what each slot reads, and the
// neighbor() constraints that can cull candidates.
#pragma once

#include <string>
#include <vector>

#include "watch/ast.h"

namespace dw::watch {

// One state variable the watchpoint reads, with every offset at which it is read.
struct VariableUse {
  std::string name;
  std::vector<int> offsets;  // sorted, distinct
  int min_offset() const { return offsets.front(); }
  int max_offset() const { return offsets.back(); }
  // Paper §IV-A: the largest difference between two offsets of the same variable.
  int span() const { return max_offset() - min_offset(); }
};

// What one slot's module contributes when it fills the slot: variable values at offsets.
struct SlotRead {
  int variable = 0;  // index into Analysis::variables
  int offset = 0;
};

// A `neighbor(x y)` term at an offset. When x is filled before y, y's candidates can be culled to
// N(x) (paper §IV-C).
struct NeighborConstraint {
  int x = 0, y = 0;
  int offset = 0;
  NodeIndex node = kNoNode;
};

struct Analysis {
  std::vector<VariableUse> variables;             // in order of first use
  std::vector<std::vector<SlotRead>> slot_reads;  // per slot, sorted by (variable, offset)
  std::vector<NeighborConstraint> neighbors;
  int extent_plus = 0;          // E+ = max(0, largest offset): how far the watchpoint looks ahead
  int min_offset = 0;           // min(0, smallest offset): how far it looks back
  int min_neighbor_offset = 0;  // min(0, smallest offset of a neighbor() term)

  int variable_index(const std::string& name) const;
};

// Requires an Ast that parsed without diagnostics.
Analysis analyze(const Ast& ast);

}  // namespace dw::watch
