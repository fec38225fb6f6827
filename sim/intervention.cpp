#include "sim/intervention.h"

#include <nlohmann/json.hpp>

namespace dw::sim {

std::string empty_cell_problem(const Lattice& lattice, ModuleId m, Intervention::Kind kind) {
  if (m >= lattice.occupied.size() || lattice.occupied[m]) return "";
  return "module " + std::to_string(m) +
         " is a cell the lattice leaves empty ([[lattice.empty]]): there is nothing to " + intervention_name(kind);
}

std::string intervention_json(const Intervention& i, const watch::Universe& universe) {
  nlohmann::ordered_json j;
  j["at"] = i.at;
  j["module"] = i.module < universe.module_count() ? universe.id(i.module) : i.module;
  switch (i.kind) {
    case Intervention::Kind::Set: j["set"] = {{universe.variables.at(static_cast<size_t>(i.column)), i.value}}; break;
    case Intervention::Kind::Remove: j["remove"] = true; break;
    case Intervention::Kind::Push: j["push"] = {i.impulse[0], i.impulse[1], i.impulse[2]}; break;
  }
  if (i.scheduled) j["scheduled"] = true;
  return j.dump();
}

}  // namespace dw::sim
