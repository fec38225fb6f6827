// Interventions (docs/design.md §7, "branches"): a change made to the ensemble from outside its programs,
// at the start of a step, before the programs run. A session makes them interactively; a scenario
// schedules them as [[event]] entries. Either way they are part of the history: the same
// interventions at the same steps give the same run.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sim/bodies.h"
#include "sim/lattice.h"
#include "watch/frame.h"

namespace dw::sim {

struct Intervention {
  enum class Kind : uint8_t {
    Set,     // the module's variable `column` takes `value`: the step's programs read it
    Remove,  // the module leaves the ensemble: absent from this step on, gone from the graph
    Push,    // an impulse `impulse` (N s) on the module's body, with the step's own requests
  };
  Kind kind = Kind::Set;
  int64_t at = 0;  // applied at the start of step `at`
  ModuleId module = 0;
  int column = 0;  // Set: the variable
  int64_t value = 0;
  Vec3 impulse{};
  bool scheduled = false;  // a scenario's [[event]]; otherwise made during a session

  bool operator==(const Intervention&) const = default;
};

inline const char* intervention_name(Intervention::Kind kind) {
  switch (kind) {
    case Intervention::Kind::Set: return "set";
    case Intervention::Kind::Remove: return "remove";
    case Intervention::Kind::Push: return "push";
  }
  return "?";
}

// Why an intervention of this kind on module m can do nothing because the lattice leaves its cell
// empty ([[lattice.empty]]), or "" when the cell holds a module: what a session and a scenario's
// [[event]] both refuse.
std::string empty_cell_problem(const Lattice& lattice, ModuleId m, Intervention::Kind kind);

// As one JSON object, the way a scenario's [[event]] says it:
// {"at":40,"module":7,"set":{"token":1}}, {"at":9,"module":3,"remove":true},
// {"at":5,"module":0,"push":[0,0,30]}; "scheduled":true for a scenario's own.
std::string intervention_json(const Intervention& intervention, const watch::Universe& universe);

}  // namespace dw::sim
