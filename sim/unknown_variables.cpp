#include "sim/unknown_variables.h"

namespace dw::sim {

std::vector<UnknownVariable> unknown_variables(const Model& model, const watch::Watchpoint& watchpoint) {
  std::vector<UnknownVariable> unknown;
  for (const std::string& v : watchpoint.program.variables)
    if (model.column(v) < 0) unknown.push_back({v, watch::first_use(watchpoint.ast, v)});
  for (const watch::Action& a : watchpoint.ast.actions) {
    if (a.kind != watch::Action::Kind::Set || model.column(a.variable) >= 0) continue;
    bool listed = false;
    for (const UnknownVariable& u : unknown) listed = listed || u.name == a.variable;
    if (!listed) unknown.push_back({a.variable, watch::first_set(watchpoint.ast, a.variable), true});
  }
  return unknown;
}

std::vector<watch::Diagnostic> unknown_variable_mistakes(const Model& model, const watch::Watchpoint& watchpoint) {
  std::vector<watch::Diagnostic> mistakes;
  for (const UnknownVariable& v : unknown_variables(model, watchpoint))
    mistakes.push_back({v.first_use, "'" + v.name + "' is no program's variable"});
  return mistakes;
}

}  // namespace dw::sim
