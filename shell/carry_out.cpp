// Shell::execute: a parsed command carried out on the session and answered. This file has the
// dispatch and the commands that move the cursor, make a new branch or change the watchpoints;
// every decision is the session's (sim/session.h), a command only asks and answers.
#include "shell/shell.h"

#include <algorithm>

#include "scenarios/scenario.h"
#include "sim/group_query.h"
#include "sim/why.h"
#include "watch/watchpoint.h"

namespace dw::shell {

using Kind = Command::Kind;

namespace {

using Answer = std::variant<nlohmann::ordered_json, std::string>;
Answer failed(std::string why) { return Answer(std::in_place_index<1>, std::move(why)); }

// why M VAR [T], why match W ROW | W T SLOTS: the cone of docs/design.md §7b. A step past the
// latest is simulated first (as a view of it would be); the cursor stays where it is.
Answer why(sim::Session& session, const Command& cmd, const sim::Control& control, nlohmann::ordered_json answer) {
  const Command::Why& asked = *cmd.why;
  std::vector<sim::ModuleId> group;
  int64_t t = asked.t.value_or(session.current());
  int w = -1;
  if (asked.match) {
    if ((w = session.watch_index(cmd.name)) < 0) return failed("no watchpoint is named '" + cmd.name + "'");
    const sim::HostedWatchpoint& h = session.watches()[static_cast<uint32_t>(w)].hosted;
    const size_t k = h.watchpoint.program.slot_count();
    if (asked.row) {
      const sim::MatchList& list = session.matches(static_cast<uint32_t>(w));
      if (*asked.row >= static_cast<int64_t>(list.size()))
        return failed("'" + cmd.name + "' lists " + std::to_string(list.size()) + " matches (`matches " + cmd.name +
                      "`): there is no row " + std::to_string(*asked.row));
      const auto row = static_cast<size_t>(*asked.row);
      t = list.t[row];
      group.assign(list.slots.begin() + static_cast<ptrdiff_t>(row * k),
                   list.slots.begin() + static_cast<ptrdiff_t>((row + 1) * k));
    } else {
      if (asked.slots.size() != k)
        return failed("'" + cmd.name + "' has " + std::to_string(k) + " slots: give " + std::to_string(k) +
                      " modules, not " + std::to_string(asked.slots.size()));
      for (int64_t m : asked.slots) group.push_back(static_cast<sim::ModuleId>(m));
    }
  }
  if (t < 0) return failed("no step has run yet: step first, or give T");
  if (t > session.latest()) {
    session.decide(t, {}, control);
    if (t > session.latest()) return failed("cancelled");
  }
  if (!session.has_history() && t < session.latest()) return failed("the session keeps no history to look back into");
  const auto cone =
      asked.match ? sim::why_match(session, static_cast<uint32_t>(w), t, group, asked.depth, asked.narrow, control)
                  : sim::why_value(session, static_cast<sim::ModuleId>(*cmd.number), asked.column, t, asked.depth,
                                   asked.narrow, control);
  if (!cone) return failed(control.stopped() ? "cancelled" : "the session keeps no history to look back into");
  std::vector<std::string> names;
  for (uint32_t i = 0; i < session.watches().size(); ++i) names.push_back(session.watches()[i].hosted.watchpoint.name);
  if (asked.match) {
    nlohmann::ordered_json slots = nlohmann::ordered_json::object();
    const sim::HostedWatchpoint& h = session.watches()[static_cast<uint32_t>(w)].hosted;
    for (size_t s = 0; s < group.size(); ++s)
      slots[h.watchpoint.program.slot_names[s]] = session.model().universe.id(group[s]);
    answer["match"] = {{"watch", cmd.name}, {"t", t}, {"slots", std::move(slots)}};
  }
  nlohmann::ordered_json found = nlohmann::ordered_json::parse(sim::cone_json(*cone, session.model().universe, names));
  for (auto& [key, value] : found.items()) answer[key] = std::move(value);
  answer["current"] = session.current();
  answer["latest"] = session.latest();
  return answer;
}

}  // namespace

Shell::Shell(const scenarios::Scenario& scenario, sim::Session& session)
    : scenario_(scenario), session_(session), bookmarks_(scenario.bookmarks) {}

std::variant<nlohmann::ordered_json, std::string> Shell::execute(const Command& cmd, const sim::Control& control) {
  nlohmann::ordered_json answer;
  answer["cmd"] = command_spec(cmd.kind).name;
  try {
    switch (cmd.kind) {
      case Kind::Step:
      case Kind::Run:
      case Kind::Continue: return run_to(cmd, control, std::move(answer));
      case Kind::Action: return set_action(cmd, std::move(answer));
      case Kind::Seek: return seek(cmd, control, std::move(answer));
      case Kind::Set:
      case Kind::Remove:
      case Kind::Push: return intervene(cmd, std::move(answer));
      case Kind::Reload: return reload(std::move(answer));
      case Kind::Watch: return set_watch(cmd, control, std::move(answer));
      case Kind::Unwatch:
        if (!session_.remove_watch(cmd.name)) return failed("no watchpoint is named '" + cmd.name + "'");
        answer["unwatched"] = cmd.name;
        break;
      case Kind::Matches: return matches(cmd, std::move(answer));
      case Kind::State: return module_state(cmd, std::move(answer));
      case Kind::Hash: return state_hash(std::move(answer));
      case Kind::Render: return render_file(cmd, control, std::move(answer));
      case Kind::Record: return record_file(cmd, control, std::move(answer));
      case Kind::Save: return save_file(cmd, std::move(answer));
      case Kind::Interventions: return interventions(std::move(answer));
      case Kind::Status: return status(std::move(answer));
      case Kind::Why: return why(session_, cmd, control, std::move(answer));
      case Kind::Find: return find(cmd, control, std::move(answer));
      case Kind::Eval: return eval(cmd, control, std::move(answer));
      case Kind::Mark:
      case Kind::Unmark:
      case Kind::Marks: return bookmark(cmd, std::move(answer));
      case Kind::Diff: return diff(cmd, control, std::move(answer));
      case Kind::Help: answer["commands"] = command_help(); break;
    }
  } catch (const sim::ProgramError& e) {
    return failed(e.what());
  } catch (const std::exception& e) {
    // A mistake of dwatch's own, not the command's: said, and the session goes on (a command
    // leaves the session as it was, or where a run had got to).
    return failed(std::string("internal error: ") + e.what());
  }
  return answer;
}

// step N, run [T] [--to-match NAME], continue: to the target step, or the pause (or the match
// asked for) that stops the run first.
Shell::Answer Shell::run_to(const Command& cmd, const sim::Control& control, nlohmann::ordered_json answer) {
  const sim::Model& model = session_.model();
  std::optional<uint32_t> to_match;
  if (cmd.kind == Kind::Run && !cmd.name.empty()) {
    const int w = session_.watch_index(cmd.name);
    if (w < 0) return failed("no watchpoint is named '" + cmd.name + "'");
    if (!sim::lists_matches(session_.watches()[static_cast<uint32_t>(w)].hosted.action))
      return failed("'" + cmd.name + "' counts its matches and keeps none to stop at ('action " + cmd.name +
                    " log' keeps them from now on)");
    to_match = static_cast<uint32_t>(w);
  }
  const int64_t target = cmd.kind == Kind::Step ? session_.current() + *cmd.number
                         : cmd.number           ? *cmd.number
                                                : std::max(session_.end() - 1, session_.current());
  std::vector<bool> stopped_before;
  for (uint32_t w = 0; w < session_.watches().size(); ++w) stopped_before.push_back(session_.stats(w).stopped);
  const auto pause = session_.run_until(target + 1, {}, control, to_match);
  add_position(answer);
  nlohmann::ordered_json stop = nullptr;
  if (pause) {
    const sim::HostedWatchpoint& h = session_.watches()[pause->watch].hosted;
    nlohmann::ordered_json group = nlohmann::ordered_json::object();
    for (size_t s = 0; s < pause->group.size(); ++s)
      group[h.watchpoint.program.slot_names[s]] = model.universe.id(pause->group[s]);
    stop = {{"watch", h.watchpoint.name},
            {"t", pause->t},
            {"detected", pause->detected},
            {"group", group},
            {"matches", pause->matches}};
  }
  // A run to a match stopped by that match says so apart from a pause action's stop.
  const bool asked = pause && pause->asked;
  answer["paused"] = asked ? nullptr : stop;
  if (to_match) answer["matched"] = asked ? stop : nullptr;
  if (control.stopped()) answer["cancelled"] = true;
  // The watchpoints a budget stopped on the way, and why, as `dwatch run` says it.
  nlohmann::ordered_json stopped = nlohmann::ordered_json::array();
  for (uint32_t w = 0; w < session_.watches().size(); ++w)
    if (session_.stats(w).stopped && (w >= stopped_before.size() || !stopped_before[w]))
      stopped.push_back({{"watch", session_.watches()[w].hosted.watchpoint.name}, {"stop_reason", stop_reason(w)}});
  if (!stopped.empty()) answer["stopped"] = std::move(stopped);
  return answer;
}

Shell::Answer Shell::set_action(const Command& cmd, nlohmann::ordered_json answer) {
  const int w = session_.watch_index(cmd.name);
  if (w < 0) return failed("no watchpoint is named '" + cmd.name + "'");
  answer["watch"] = cmd.name;
  answer["was"] = std::string(sim::action_name(session_.watches()[static_cast<uint32_t>(w)].hosted.action));
  session_.set_action(static_cast<uint32_t>(w), cmd.action);
  answer["action"] = std::string(sim::action_name(cmd.action));
  return answer;
}

Shell::Answer Shell::seek(const Command& cmd, const sim::Control& control, nlohmann::ordered_json answer) {
  if (*cmd.number > session_.latest())
    return failed("step " + std::to_string(*cmd.number) + " has not been simulated (the latest is " +
                  std::to_string(session_.latest()) + "; step or run to get there)");
  if (!session_.seek(*cmd.number, control)) {
    if (control.stopped()) return failed("cancelled");
    return failed("the session keeps no history to seek back to");
  }
  add_position(answer);
  return answer;
}

// find prev|next M VAR | M... when TEXT: the cursor goes to the nearest step found; it stays when
// none is, and the answer says how far the search went (step 0, or the latest).
Shell::Answer Shell::find(const Command& cmd, const sim::Control& control, nlohmann::ordered_json answer) {
  const Command::Query& q = *cmd.query;
  if (!session_.has_history()) return failed("the session keeps no history to search");
  const auto direction = q.back ? sim::SearchDirection::Back : sim::SearchDirection::On;
  const sim::Found found = q.condition ? sim::find_holding(session_, q.condition->program, q.group, direction, control)
                                       : sim::find_change(session_, q.group[0], q.column, direction, control);
  if (found.cancelled) return failed("cancelled");
  if (found.step && !session_.seek(*found.step, control)) return failed("cancelled");
  answer["found"] = found.step ? nlohmann::ordered_json(*found.step) : nlohmann::ordered_json(nullptr);
  if (!found.step) answer["searched_to"] = q.back ? int64_t{0} : session_.latest();
  add_position(answer);
  return answer;
}

// mark T [NOTE], unmark T, marks: the bookmarks, each answered with the list as it stands.
Shell::Answer Shell::bookmark(const Command& cmd, nlohmann::ordered_json answer) {
  if (cmd.kind == Kind::Mark) bookmarks_.mark(*cmd.number, cmd.name);
  if (cmd.kind == Kind::Unmark && !bookmarks_.unmark(*cmd.number))
    return failed("step " + std::to_string(*cmd.number) + " has no bookmark ('marks' lists them)");
  nlohmann::ordered_json marks = nlohmann::ordered_json::array();
  for (const sim::Bookmark& b : bookmarks_.all()) marks.push_back({{"at", b.at}, {"note", b.note}});
  answer["marks"] = std::move(marks);
  return answer;
}

// set, remove, push: an intervention at the current step, which starts a new branch.
Shell::Answer Shell::intervene(const Command& cmd, nlohmann::ordered_json answer) {
  const int64_t dropped = session_.latest() - session_.current();
  const std::string stuck = cmd.kind == Kind::Push ? session_.push_moves_nothing(cmd.intervention->module) : "";
  if (std::string error = session_.intervene(*cmd.intervention); !error.empty()) return failed(error);
  sim::Intervention made = *cmd.intervention;
  made.at = session_.current() + 1;
  answer["intervention"] = intervention_answer(made);
  answer["dropped_steps"] = dropped;
  add_position(answer);
  if (!stuck.empty()) answer["warning"] = stuck;
  return answer;
}

Shell::Answer Shell::reload(nlohmann::ordered_json answer) {
  if (scenario_.scripts.empty()) return failed("the scenario runs no Lua script to reload");
  const int64_t dropped = session_.latest() - session_.current();
  auto reloaded = scenarios::reload_scripts(scenario_, session_);
  if (auto* error = std::get_if<std::string>(&reloaded)) return failed(*error);
  answer["reloaded"] = std::get<std::vector<std::string>>(reloaded);
  answer["from"] = session_.current() + 1;
  answer["dropped_steps"] = dropped;
  add_position(answer);
  return answer;
}

// watch: a watchpoint added or replaced, evaluated over the whole history at once.
Shell::Answer Shell::set_watch(const Command& cmd, const sim::Control& control, nlohmann::ordered_json answer) {
  std::string why;
  const auto w = session_.set_watch(*cmd.watch, control, &why);
  if (!w) return failed(why);
  const sim::HostedWatchpoint& h = session_.watches()[*w].hosted;
  const sim::WatchSpec spec = sim::spec_of(h);
  answer["watch"] = spec.name;
  answer["index"] = *w;
  answer["algorithm"] = spec.algorithm_name();
  answer["shape"] = spec.shape_name();
  answer["action"] = sim::action_name(spec.action);
  answer["lag"] = h.lag();
  answer["matches"] = session_.match_count(*w);
  answer["decided"] = session_.decided(*w);
  if (session_.stats(*w).stopped) {  // a budget stopped it on the history
    answer["stopped"] = true;
    answer["stop_reason"] = stop_reason(*w);
  }
  return answer;
}

}  // namespace dw::shell
