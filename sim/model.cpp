#include "sim/model.h"

#include <algorithm>
#include <unordered_map>

namespace dw::sim {

int Model::column(std::string_view name) const {
  const auto& v = universe.variables;
  const auto it = std::find(v.begin(), v.end(), name);
  return it == v.end() ? -1 : static_cast<int>(it - v.begin());
}

std::variant<std::unique_ptr<Model>, std::string> build_model(Lattice lattice,
                                                              std::vector<std::unique_ptr<const HostProgram>> programs,
                                                              std::vector<HostedWatchpoint> watches, uint64_t seed) {
  auto model = std::make_unique<Model>();
  const uint32_t modules = static_cast<uint32_t>(lattice.spec.module_count());
  model->lattice = std::move(lattice);
  model->seed = seed;
  model->universe.identity_count = modules;
  std::vector<std::string_view> owner;
  // Columns by name: a script may declare hundreds of thousands of variables (Model::column
  // searches the list, which made this loop quadratic).
  std::unordered_map<std::string, int> columns;
  for (const auto& program : programs) {
    model->program_base.push_back(model->variable_count());
    for (VariableSpec& v : program->variables()) {
      const auto [it, added] = columns.try_emplace(v.name, int(model->variable_count()));
      const int existing = added ? -1 : it->second;
      if (existing >= 0 && size_t(existing) >= model->program_base.back())
        return "program " + std::string(program->name()) + " declares the variable '" + v.name + "' twice";
      if (existing >= 0 && owner[size_t(existing)] == program->name())
        return "two [[program]] tables run " + std::string(program->name()) + ", and both declare the variable '" +
               v.name + "'";
      if (existing >= 0)
        return "programs " + std::string(owner[size_t(existing)]) + " and " + std::string(program->name()) +
               " both declare the variable '" + v.name + "'";
      model->universe.variables.push_back(std::move(v.name));
      model->initial_values.push_back(v.initial);
      owner.push_back(program->name());
    }
  }
  model->programs = std::move(programs);
  model->watches = std::move(watches);
  return model;
}

}  // namespace dw::sim
