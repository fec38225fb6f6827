// A watchpoint that reads a variable no program of the model has would read it as unknown for
// ever and never match: the scenario loader, the session language and the Python package refuse
// it, each in its own words, over the one list this finds.
#pragma once

#include <string>
#include <vector>

#include "sim/model.h"
#include "watch/diagnostic.h"
#include "watch/watchpoint.h"

namespace dw::sim {

struct UnknownVariable {
  std::string name;
  watch::Span first_use;  // where the watchpoint first reads it (or, if it only sets it, sets it)
  bool only_set = false;  // named only by a 'then set'
};

// The variables `watchpoint` reads that no program of `model` has, in the order it reads them,
// then those its actions set that no program has (a set no module could take).
std::vector<UnknownVariable> unknown_variables(const Model& model, const watch::Watchpoint& watchpoint);

// A mistake for each, at its first use: "'v' is no program's variable" (the session language's
// and the Python package's words).
std::vector<watch::Diagnostic> unknown_variable_mistakes(const Model& model, const watch::Watchpoint& watchpoint);

}  // namespace dw::sim
