// The commands that only read the session (matches, state, hash, interventions, status, eval, diff), and the
// pieces of JSON the answers share: the cursor's position, a match as the match log writes it,
// an intervention.
#include "shell/shell.h"

#include "sim/group_query.h"
#include "sim/match_log.h"
#include "sim/state.h"
#include "sim/step_diff.h"
#include "sim/watch_hosting.h"
#include "watch/watchpoint.h"

namespace dw::shell {

void Shell::add_position(nlohmann::ordered_json& answer) {
  answer["current"] = session_.current();
  answer["latest"] = session_.latest();
  answer["decided"] = session_.decided();
}

nlohmann::ordered_json Shell::intervention_answer(const sim::Intervention& intervention) const {
  return nlohmann::ordered_json::parse(sim::intervention_json(intervention, session_.model().universe));
}

nlohmann::ordered_json Shell::match_json(uint32_t w, size_t i) const {
  const sim::HostedWatchpoint& h = session_.watches()[w].hosted;
  const sim::MatchList& list = session_.matches(w);
  const size_t k = h.watchpoint.program.slot_count();
  nlohmann::ordered_json j;
  j["watch"] = h.watchpoint.name;
  j["t"] = list.t[i];
  nlohmann::ordered_json slots = nlohmann::ordered_json::object();
  for (size_t s = 0; s < k; ++s)
    slots[h.watchpoint.program.slot_names[s]] = session_.model().universe.id(list.slots[i * k + s]);
  j["slots"] = std::move(slots);
  if (const size_t a = h.watchpoint.program.actions.size(); a > 0 && list.actions.size() >= (i + 1) * a) {
    std::vector<watch::ModuleId> ids;
    for (size_t s = 0; s < k; ++s) ids.push_back(session_.model().universe.id(list.slots[i * k + s]));
    j["then"] = sim::MatchLog::then_json(sim::MatchLog::info(h.watchpoint), ids, {list.actions.data() + i * a, a});
  }
  j["detected"] = list.detected[i];
  return j;
}

std::string Shell::stop_reason(uint32_t w) const { return sim::stop_text(session_.stats(w).stop_reason, "max_live"); }

Shell::Answer Shell::matches(const Command& cmd, nlohmann::ordered_json answer) {
  const sim::WatchSlots& watches = session_.watches();
  int w = -1;
  if (!cmd.name.empty() && (w = session_.watch_index(cmd.name)) < 0)
    return failed("no watchpoint is named '" + cmd.name + "'");
  // A `count` watchpoint keeps only the number of its matches of each step, not the groups.
  // Its action may have changed on the way (`action W count`, then `log`): what it kept is
  // listed and what it counted answered under only_counted, whatever its action is now.
  nlohmann::ordered_json list = nlohmann::ordered_json::array(), only_counted = nlohmann::ordered_json::object();
  uint64_t counted = 0;
  for (uint32_t i = 0; i < watches.size(); ++i) {
    if (w >= 0 && i != static_cast<uint32_t>(w)) continue;
    const sim::MatchList& m = session_.matches(i);
    const uint64_t n = cmd.number ? m.counted_at(*cmd.number) : m.counted_total();
    if (n > 0 || !sim::lists_matches(watches[i].hosted.action)) {
      only_counted[watches[i].hosted.watchpoint.name] = n;
      counted += n;
    }
    const auto [first, last] = cmd.number ? m.at(*cmd.number) : std::pair<size_t, size_t>{0, m.size()};
    for (size_t k = first; k < last; ++k) list.push_back(match_json(i, k));
  }
  if (cmd.number) {
    answer["t"] = *cmd.number;
    answer["decided"] = *cmd.number <= session_.decided();
  }
  answer["count"] = list.size() + counted;
  if (!only_counted.empty()) answer["only_counted"] = std::move(only_counted);
  answer["matches"] = std::move(list);
  return answer;
}

// state M: the module at the current step t, as its program and its neighbours see it: its
// variables and N(m, t); with bodies, its pose after step t's physics (`pose`) and the one its
// neighbours were measured from (`nbrs_measured_from`, at the end of step t - 1: docs/design.md
// §2; null if the session's history cannot give it).
Shell::Answer Shell::module_state(const Command& cmd, nlohmann::ordered_json answer) {
  const sim::Model& model = session_.model();
  const auto m = static_cast<sim::ModuleId>(*cmd.number);
  // Read first: it may take the view back a step, and a state read before would be that step's.
  const std::optional<sim::Pose> measured = session_.measured_pose(m);
  const sim::State& s = session_.state();
  const int64_t t = session_.current();
  answer["t"] = t;
  answer["module"] = model.universe.id(m);
  answer["present"] = session_.seen_present()[m] != 0;
  nlohmann::ordered_json vars = nlohmann::ordered_json::object();
  for (uint32_t v = 0; v < model.variable_count(); ++v)
    vars[model.universe.variables[v]] = s.values[size_t{m} * model.variable_count() + v];
  answer["vars"] = std::move(vars);
  nlohmann::ordered_json nbrs = nlohmann::ordered_json::array();
  for (sim::ModuleId n : session_.seen_graph().neighbors(m)) nbrs.push_back(model.universe.id(n));
  answer["nbrs"] = std::move(nbrs);
  if (!s.bodies.empty()) {
    const sim::Pose p = s.bodies.poses[m];
    answer["pose"] = {{"position", p.position}, {"orientation", p.orientation}};
    // Before step 0 (t = -1) the graph is the initial state's, measured from its own poses.
    answer["nbrs_measured_from"] = measured ? nlohmann::ordered_json{{"t", std::max<int64_t>(t - 1, -1)},
                                                                     {"position", measured->position},
                                                                     {"orientation", measured->orientation}}
                                            : nlohmann::ordered_json(nullptr);
  }
  return answer;
}

// eval M... TEXT: the condition on the group at the current step, true, false or null (unknown: it
// reads a step not simulated yet or a module absent then).
Shell::Answer Shell::eval(const Command& cmd, const sim::Control& control, nlohmann::ordered_json answer) {
  const int64_t t = session_.current();
  if (t < 0) return failed("no step has run yet: step first");
  if (!session_.has_history()) return failed("the session keeps no history to read the condition from");
  const auto truths = sim::truth_over(session_, cmd.query->condition->program, cmd.query->group, t, t, control);
  if (!truths) return failed("cancelled");
  const watch::Truth truth = truths->front();
  answer["t"] = t;
  answer["value"] =
      truth == watch::kUnknown ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(truth == watch::kTrue);
  return answer;
}

// diff T1 T2: each module that differs, its variables as [at T1, at T2], its presence when that
// differs, the neighbours it gained and lost; the first kDiffRows modules, and how many in all.
Shell::Answer Shell::diff(const Command& cmd, const sim::Control& control, nlohmann::ordered_json answer) {
  constexpr size_t kDiffRows = 1000;
  if (!session_.has_history()) return failed("the session keeps no history to compare");
  for (const int64_t t : {*cmd.number, *cmd.other})
    if (t > session_.latest())
      return failed("step " + std::to_string(t) + " has not been simulated (the latest is " +
                    std::to_string(session_.latest()) + ")");
  const auto d = sim::diff_steps(session_, *cmd.number, *cmd.other, kDiffRows, control);
  if (!d) return failed(control.stopped() ? "cancelled" : "the session keeps no history to compare");
  const sim::Model& model = session_.model();
  auto ids = [&](const std::vector<sim::ModuleId>& ms) {
    nlohmann::ordered_json j = nlohmann::ordered_json::array();
    for (sim::ModuleId m : ms) j.push_back(model.universe.id(m));
    return j;
  };
  answer["a"] = d->a;
  answer["b"] = d->b;
  answer["count"] = d->total;
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const sim::ModuleDiff& m : d->modules) {
    nlohmann::ordered_json row = {{"module", model.universe.id(m.module)}};
    if (m.present_a != m.present_b) row["present"] = {m.present_a, m.present_b};
    if (!m.values.empty()) {
      nlohmann::ordered_json vars = nlohmann::ordered_json::object();
      for (const sim::ModuleDiff::Value& v : m.values) vars[model.universe.variables[size_t(v.column)]] = {v.a, v.b};
      row["vars"] = std::move(vars);
    }
    if (!m.gained.empty()) row["gained"] = ids(m.gained);
    if (!m.lost.empty()) row["lost"] = ids(m.lost);
    rows.push_back(std::move(row));
  }
  answer["modules"] = std::move(rows);
  if (d->total > d->modules.size()) answer["more"] = d->total - d->modules.size();
  return answer;
}

Shell::Answer Shell::state_hash(nlohmann::ordered_json answer) {
  const sim::StateHash hash = session_.hash();
  answer["t"] = session_.current();
  answer["hash"] = sim::hash_text(hash.whole());
  answer["simulation"] = sim::hash_text(hash.simulation);
  answer["watchpoints"] = sim::hash_text(hash.watches);
  answer["run"] = sim::hash_text(hash.run);
  return answer;
}

Shell::Answer Shell::interventions(nlohmann::ordered_json answer) {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const sim::Intervention& i : session_.interventions()) list.push_back(intervention_answer(i));
  answer["interventions"] = std::move(list);
  return answer;
}

Shell::Answer Shell::status(nlohmann::ordered_json answer) {
  add_position(answer);
  answer["end"] = session_.end();
  nlohmann::ordered_json watches = nlohmann::ordered_json::array();
  for (uint32_t w = 0; w < session_.watches().size(); ++w) {
    const sim::HostedWatchpoint& h = session_.watches()[w].hosted;
    const sim::WatchSpec spec = sim::spec_of(h);
    watches.push_back({{"name", spec.name},
                       {"algorithm", spec.algorithm_name()},
                       {"shape", spec.shape_name()},
                       {"action", sim::action_name(spec.action)},
                       {"lag", h.lag()},
                       {"decided", session_.decided(w)},
                       {"matches", session_.match_count(w)},
                       {"stopped", session_.stats(w).stopped}});
    if (session_.stats(w).stopped) watches.back()["stop_reason"] = stop_reason(w);
  }
  answer["watches"] = std::move(watches);
  answer["interventions"] = session_.interventions().size();
  // How the history is kept: it varies with the machine's speed (never the results).
  answer["history"] = {{"keyframe_interval", session_.keyframe_interval()},
                       {"keyframes", session_.keyframes()},
                       {"bytes", session_.history_bytes()}};
  return answer;
}

}  // namespace dw::shell
