// Static analysis of a parsed watchpoint (paper §IV-A, docs/design.md §3 and §4b): the temporal offset of
// every term, each variable's temporal span, the temporal extent E+, what each slot reads, what
// each neighbour aggregate reads, and the neighbor() constraints that can cull candidates.
#pragma once

#include <string>
#include <vector>

#include "watch/ast.h"

namespace dw::watch {

// One state variable the watchpoint reads, with every offset at which it is read (a neighbour's,
// read in an aggregate, at the aggregate's offset plus its own).
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

// A `neighbor(x y)` term between two slots, outside any aggregate, at an offset. When x is filled
// before y, y's candidates can be culled to N(x) (paper §IV-C).
struct NeighborConstraint {
  int x = 0, y = 0;
  int offset = 0;
  NodeIndex node = kNoNode;
};

// A neighbour aggregate `count(n in neighbors(a.last): ...)`: the slot and offset whose neighbours
// it ranges over, and what it reads of each neighbour (offsets from the aggregate's step).
struct AggregateUse {
  NodeIndex node = kNoNode;
  int slot = 0, offset = 0;
  Domain domain = Domain::Neighbors;
  int hops = 1;                          // within's h
  std::vector<SlotRead> neighbor_reads;  // n.v at an offset, sorted, distinct
  std::vector<int> neighbor_sets;        // offsets at which neighbor(n ...) reads N(n), sorted, distinct
  std::vector<int> slots;                // the slots its body reads, besides its own, sorted
  // Whether an agent needs its neighbours' messages to know it (docs/design.md §7): it reads their
  // variables or their neighbour sets, not only its own neighbour set.
  bool needs_messages() const { return !neighbor_reads.empty() || !neighbor_sets.empty(); }
  // Steps of messages a distributed agent waits to know it (docs/design.md §4c): within's h rounds
  // (who lies within h hops, and what they hold); one hop for neighbours' values; none for its own
  // neighbour set, or for `all`, a fact of the engine's snapshot.
  int lag() const {
    if (domain == Domain::Within) return hops;
    if (domain == Domain::All || domain == Domain::Component) return 0;
    return needs_messages() ? 1 : 0;
  }
};

struct Analysis {
  std::vector<VariableUse> variables;             // in order of first use
  std::vector<std::vector<SlotRead>> slot_reads;  // per slot, sorted by (variable, offset)
  std::vector<NeighborConstraint> neighbors;
  std::vector<AggregateUse> aggregates;  // in source order
  int extent_plus = 0;                   // E+ = max(0, largest offset): how far the watchpoint looks ahead
  int min_offset = 0;                    // min(0, smallest offset): how far it looks back
  int min_neighbor_offset = 0;           // min(0, smallest offset at which a neighbour set is read)
  // Steps a distributed agent waits for what its aggregates read (docs/design.md §7, §4c): the largest
  // AggregateUse::lag. Part of the distributed readings' lag.
  int aggregate_hops = 0;

  int variable_index(const std::string& name) const;
};

// Requires an Ast that parsed without diagnostics.
Analysis analyze(const Ast& ast);

}  // namespace dw::watch
