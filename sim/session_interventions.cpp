// The session's interventions and reloaded programs (docs/design.md §7, "branches"): each made at
// the current step, dropping the future after it.
#include <algorithm>

#include "sim/session.h"

namespace dw::sim {

std::string Session::push_moves_nothing(ModuleId m) {
  const Bodies& b = state().bodies;
  if (m >= b.cluster_of.size()) return {};
  const std::string who = "module " + std::to_string(m), when = " at step " + std::to_string(current_);
  if (b.moving(m))
    return who + " is making a lattice move" + when + ": it glides along its path whatever pushes it, so the push " +
           "moves nothing";
  const uint32_t c = b.cluster_of[m];
  if (c != kNoCluster && b.clusters[c].anchored)
    return who + " is latched to the ground" + when + " (its cluster of " + std::to_string(b.clusters[c].count) +
           " modules is anchored): the push moves nothing unless a program's move frees it in the next step";
  return {};
}

std::string Session::intervene(Intervention i) {
  i.at = current_ + 1;
  i.scheduled = false;
  if (i.module >= model_.module_count())
    return "module " + std::to_string(i.module) + " is not in the ensemble (ids 0.." +
           std::to_string(static_cast<int64_t>(model_.module_count()) - 1) + ")";
  if (i.kind == Intervention::Kind::Set && (i.column < 0 || static_cast<uint32_t>(i.column) >= model_.variable_count()))
    return "no program has that variable";
  if (i.kind == Intervention::Kind::Push && head_.bodies.empty())
    return "push needs bodies, and this scenario has no physics";
  {  // a module removed keeps its variables and body where they were, read by nothing: a set or
     // push on it would change nothing the run shows, and the intervention would be kept for naught
    const State& now = state();
    const bool queued = std::any_of(interventions_.begin(), interventions_.end(), [&](const Intervention& o) {
      return o.at == i.at && o.kind == Intervention::Kind::Remove && o.module == i.module;
    });
    if (std::string problem = empty_cell_problem(model_.lattice, i.module, i.kind); !problem.empty()) return problem;
    if (queued || (i.module < now.present.size() && !now.present[i.module]))
      return "module " + std::to_string(i.module) + " is already gone at step " + std::to_string(i.at) +
             ": there is nothing to " + intervention_name(i.kind);
  }
  if (current_ < latest_ && !has_history()) return "the session keeps no history to branch from";
  const int64_t simulated_before = latest_;
  if (current_ < latest_) branch_here();
  drop_changes_after(i.at);
  const auto after = std::upper_bound(interventions_.begin(), interventions_.end(), i,
                                      [](const Intervention& a, const Intervention& b) { return a.at < b.at; });
  interventions_.insert(after, i);
  decide_again(simulated_before);
  return {};
}

// A branch starts at the current step, which had been decided: it is decided again on the branch
// before the cursor stands on it (design §7, views show a step only once every watchpoint has
// decided it). Without this a match the cursor paused on, found by a watchpoint with lag λ at
// t + λ, is gone from the branch until it is run on, although step t itself is unchanged. As far
// as the run had gone before, and never past the scenario's end (as `run` looks ahead).
void Session::decide_again(int64_t simulated_before) {
  if (drained_) return;  // `dwatch run`'s last call: no further step
  int64_t need = current_ + max_lag();
  need = std::min(need, options_.end > 0 ? std::max(options_.end - 1, simulated_before) : simulated_before);
  while (latest_ < need) step_head({});
}

// What was made in a dropped future goes with it; the scenario's schedule stays.
void Session::drop_changes_after(int64_t at) {
  failure_.reset();  // the steps after `at` will run otherwise
  std::erase_if(interventions_, [&](const Intervention& x) { return x.at > at && !x.scheduled; });
  std::erase_if(program_versions_, [&](const ProgramVersion& v) { return v.from > at; });
}

std::string Session::replace_programs(std::vector<Replacement> replacements) {
  for (const Replacement& r : replacements) {
    if (r.program >= model_.program_count()) return "there is no program " + std::to_string(r.program);
    if (!same_variables(*r.with, *model_.programs[r.program]))
      return std::string(r.with->name()) +
             " now declares other variables than the run has; a program replaced in a run must keep them (load the "
             "scenario again instead)";
  }
  if (current_ < latest_ && !has_history()) return "the session keeps no history to branch from";
  const int64_t simulated_before = latest_;
  if (current_ < latest_) branch_here();
  const int64_t from = current_ + 1;
  drop_changes_after(from);
  for (Replacement& r : replacements) program_versions_.push_back({from, r.program, std::move(r.with)});
  decide_again(simulated_before);
  return {};
}

}  // namespace dw::sim
