#include "app/view/readout.h"

#include <algorithm>

#include "shell/view_image.h"
#include "sim/intervention.h"
#include "watch/detector.h"

namespace dw::view {

std::string slots_text(const sim::Session& session, uint32_t watch, std::span<const sim::ModuleId> group) {
  const sim::Model& model = session.model();
  const auto& names = session.watches()[watch].hosted.watchpoint.program.slot_names;
  if (names.empty()) return "(no module)";  // a zero-slot watchpoint's match (docs/design.md §4c)
  std::string s;
  for (size_t i = 0; i < group.size() && i < names.size(); ++i)
    s += (s.empty() ? "" : " ") + names[i] + "=" + std::to_string(model.universe.id(group[i]));
  return s;
}

std::optional<ModuleWindow> read_module_window(sim::Session& session, sim::ModuleId m, int64_t steps,
                                               const sim::Control& control) {
  ModuleWindow w;
  w.module = m;
  w.to = session.latest();
  w.interventions = session.interventions().size();
  w.from = std::max<int64_t>(0, w.to - steps + 1);
  if (w.to < 0) return w;
  auto rows = session.module_series(m, w.from, w.to, control);
  if (!rows) return std::nullopt;
  w.rows = std::move(*rows);
  return w;
}

bool window_holds(const ModuleWindow& window, const sim::Session& session, sim::ModuleId m) {
  return window.module == m && window.to == session.latest() &&
         window.interventions == session.interventions().size() && session.current() >= window.from &&
         session.current() <= window.to && !window.rows.empty();
}

namespace {

std::vector<sim::ModuleId> group_of(const sim::Session& session, MatchRef r) {
  const size_t k = size_t(session.watches()[r.watch].hosted.watchpoint.program.slot_count());
  const sim::MatchList& list = session.matches(r.watch);
  return {list.slots.begin() + std::ptrdiff_t(r.index * k), list.slots.begin() + std::ptrdiff_t((r.index + 1) * k)};
}

// A match as a row of the matches table (and of the Module panel's list).
MatchRowText match_row(const sim::Session& session, MatchRef r) {
  const sim::MatchList& list = session.matches(r.watch);
  return {r, session.watches()[r.watch].hosted.watchpoint.name, list.t[r.index], list.detected[r.index],
          slots_text(session, r.watch, group_of(session, r))};
}

Inspector inspect(sim::Session& session, const ViewModel& view, const ModuleWindow* window,
                  const ReadoutLimits& limits) {
  const sim::Model& model = session.model();
  const sim::ModuleId m = *view.selected;
  Inspector in;
  in.module = m;
  const sim::State& s = session.state();
  const size_t v = model.variable_count();
  const int64_t t = session.current();
  in.present = t >= 0 && session.seen_present()[m] != 0;
  const bool have_window = window && window_holds(*window, session, m);
  for (uint32_t c = 0; c < v; ++c) {
    VariableRow row{model.universe.variables[c], s.values[size_t{m} * v + c], std::nullopt};
    if (have_window && t - 1 >= window->from) row.before = window->rows[size_t(t - 1 - window->from) * v + c];
    in.variables.push_back(std::move(row));
  }
  if (t >= 0)
    for (sim::ModuleId n : session.seen_graph().neighbors(m)) in.neighbors.push_back(n);
  if (!s.bodies.empty()) in.pose = s.bodies.poses[m];
  MatchFilter only_m;
  only_m.module = m;
  MatchRows rows = filter_matches(session, only_m, limits.module_matches);
  for (const MatchRef& r : rows.rows) in.matches.push_back(match_row(session, r));
  in.matches_total = rows.total;
  in.plot_column = view.plot_variable.empty() ? 0 : std::max(0, model.column(view.plot_variable));
  if (have_window) {
    in.plot_from = window->from;
    for (size_t i = size_t(in.plot_column); i < window->rows.size(); i += v) in.plot.push_back(window->rows[i]);
  }
  return in;
}

// The group's lines in the Module plot, when the inspected module fills one of its slots and the
// series are this group's, of the plotted variable, over the plot's steps.
void overlay_group(Inspector& in, const GroupTable& group, const sim::Session& session, const GroupSeries& series) {
  const auto at = std::ranges::find(group.modules, in.module);
  if (at == group.modules.end() || in.plot.empty() ||
      !series.holds(group.modules, in.plot_column, session.latest(), session.interventions().size()) ||
      series.from != in.plot_from)
    return;
  const watch::Universe& universe = session.model().universe;
  auto label = [&](size_t slot) { return group.slots[slot] + "=" + std::to_string(universe.id(group.modules[slot])); };
  in.plot_label = label(size_t(at - group.modules.begin()));
  for (size_t slot = 0; slot < group.modules.size(); ++slot)
    if (group.modules[slot] != in.module && series.values[slot].size() == in.plot.size())
      in.plot_group.push_back({label(slot), series.values[slot]});
}

}  // namespace

Readout read_readout(sim::Session& session, const scenarios::Scenario& scenario, const ViewModel& view,
                     const ReadoutRequest& request, const ReadoutLimits& limits) {
  const sim::Model& model = session.model();
  Readout readout;
  readout.version = request.version;
  readout.timeline = request.timeline;
  readout.columns = request.columns;
  readout.at = {session.current(), session.latest(), session.end()};
  readout.decided = session.decided();
  readout.history_bytes = session.history_bytes();
  readout.keyframes = session.keyframes();
  readout.keyframe_interval = session.keyframe_interval();
  readout.failure = session.failure();

  for (uint32_t w = 0; w < session.watches().size(); ++w) {
    const sim::HostedWatchpoint& h = session.watches()[w].hosted;
    WatchRow row;
    row.spec = sim::spec_of(h);
    row.spec.text = h.watchpoint.source->text();
    row.lag = h.lag();
    row.matches = session.match_count(w);
    row.slots = size_t(h.watchpoint.program.slot_count());
    const std::vector<int64_t>& steps = session.matches(w).t;
    const int64_t now = readout.at.current;
    if (auto p = previous_match(steps, now)) row.nearest_steps.push_back(*p);
    if (auto n = next_match(steps, now)) row.nearest_steps.push_back(*n);
    row.lane = lane_density(steps, request.timeline, request.columns);
    readout.watches.push_back(std::move(row));

    // The detector's statistics of the steps up to the current one.
    std::vector<StatsRow> stats;
    const watch::DetectorStats& ds = session.stats(w);
    const int64_t t = std::max<int64_t>(0, readout.at.current);
    for (const watch::StepStats& st : ds.steps) {
      if (st.step > t || st.step <= t - limits.stats_steps) continue;
      stats.push_back({st.step, st.live, st.created, st.messages, st.matches, st.seconds, st.live_by_filled});
    }
    readout.stats.push_back(std::move(stats));
  }

  for (const sim::Intervention& i : session.interventions()) {
    readout.intervention_steps.push_back(i.at);
    readout.interventions.push_back(sim::intervention_json(i, model.universe));
  }

  // The scene highlights one group of the current step, linked and labelled: the selected match
  // when it is of this step, else the first (as `dwatch render` draws a step). The timeline and
  // the matches table show the others.
  const int64_t t = std::max<int64_t>(0, readout.at.current);
  std::vector<render::SceneGroup> groups;
  if (readout.at.current >= 0) groups = shell::groups_at(session, t, shell::Highlight::First);
  if (const auto& chosen = view.selected_match; chosen && chosen->watch < session.watches().size() &&
                                                chosen->index < session.matches(chosen->watch).size() &&
                                                session.matches(chosen->watch).t[chosen->index] == t) {
    const watch::Watchpoint& wp = session.watches()[chosen->watch].hosted.watchpoint;
    groups = {{wp.name, t, wp.program.slot_names, group_of(session, *chosen)}};
  }
  render::SceneSettings settings = shell::scene_settings(scenario, view.color_by);
  settings.selected = view.selected;
  settings.contacts = view.contacts;
  readout.physics = !session.state().bodies.empty();
  settings.title = scenario.name + "  \xC2\xB7  step " + std::to_string(t);
  readout.scene = render::build_scene(model, session.state(), groups, settings);
  // Once a watchpoint has matched, the ensemble stays faded at every step, group or none: stepping
  // and playing, it no longer flickers between faded and vivid as matches come and go.
  for (uint32_t w = 0; w < session.watches().size(); ++w)
    readout.scene.fade_others = readout.scene.fade_others || session.matches(w).size() > 0;
  readout.scene.isolate = view.isolate;
  if (view.cut_axis >= 0) readout.scene.cut = render::Scene::Cut{view.cut_axis, view.cut_at};
  if (const int c = settings.color_by.empty() ? -1 : model.column(settings.color_by); c >= 0) {
    const sim::State& s = session.state();
    const size_t v = model.variable_count();
    for (size_t m = 0; m < model.module_count(); ++m) readout.color_values.push_back(s.values[m * v + size_t(c)]);
  }

  if (view.selected && *view.selected < model.module_count())
    readout.inspector = inspect(session, view, request.window, limits);
  readout.group = read_group_table(session, view, request.group_window);
  if (readout.inspector && readout.group && request.group_series)
    overlay_group(*readout.inspector, *readout.group, session, *request.group_series);

  if (request.keep_rows) {
    readout.match_rows = request.keep_rows->match_rows;
    readout.match_total = request.keep_rows->match_total;
    return readout;
  }
  MatchRows rows = filter_matches(session, view.filter, limits.match_rows);
  readout.match_total = rows.total;
  for (const MatchRef& r : rows.rows) readout.match_rows.push_back(match_row(session, r));
  return readout;
}

nlohmann::ordered_json Readout::panel(const std::string& name, const sim::Model& model) const {
  nlohmann::ordered_json j;
  j["panel"] = name;
  if (name == "position") {
    j["current"] = at.current;
    j["latest"] = at.latest;
    j["decided"] = decided;
    if (failure)
      j["failure"] = {
          {"step", failure->step}, {"module", model.universe.id(failure->module)}, {"message", failure->message}};
  } else if (name == "matches") {
    j["total"] = match_total;
    nlohmann::ordered_json rows = nlohmann::ordered_json::array();
    for (const MatchRowText& r : match_rows)
      rows.push_back({{"watch", r.watch}, {"t", r.t}, {"detected", r.detected}, {"slots", r.slots}});
    j["rows"] = std::move(rows);
  } else if (name == "watchpoints") {
    nlohmann::ordered_json rows = nlohmann::ordered_json::array();
    for (const WatchRow& w : watches)
      rows.push_back({{"name", w.spec.name},
                      {"algorithm", w.spec.algorithm_name()},
                      {"action", sim::action_name(w.spec.action)},
                      {"lag", w.lag},
                      {"matches", w.matches}});
    j["rows"] = std::move(rows);
  } else if (name == "inspector") {
    if (!inspector) {
      j["module"] = nullptr;
      return j;
    }
    const Inspector& in = *inspector;
    j["module"] = model.universe.id(in.module);
    j["t"] = at.current;
    j["present"] = in.present;
    nlohmann::ordered_json vars = nlohmann::ordered_json::array();
    for (const VariableRow& v : in.variables) {
      nlohmann::ordered_json row = {{"name", v.name}, {"value", v.value}};
      if (v.before) row["before"] = *v.before;
      row["changed"] = v.changed();
      vars.push_back(std::move(row));
    }
    j["vars"] = std::move(vars);
    nlohmann::ordered_json nbrs = nlohmann::ordered_json::array();
    for (sim::ModuleId n : in.neighbors) nbrs.push_back(model.universe.id(n));
    j["nbrs"] = std::move(nbrs);
    j["matches"] = in.matches_total;
    j["plot"] = {{"variable", model.universe.variables[size_t(in.plot_column)]},
                 {"from", in.plot_from},
                 {"points", in.plot.size()}};
    if (!in.plot_group.empty()) {
      j["plot"]["lines"] = {in.plot_label};
      for (const PlotOverlay& o : in.plot_group) j["plot"]["lines"].push_back(o.label);
    }
  } else if (name == "group") {
    if (!group) {
      j["group"] = nullptr;
      return j;
    }
    const GroupTable& g = *group;
    j["t"] = at.current;
    j["match_t"] = g.t;
    nlohmann::ordered_json slots = nlohmann::ordered_json::object();
    for (size_t i = 0; i < g.slots.size(); ++i) slots[g.slots[i]] = model.universe.id(g.modules[i]);
    j["group"] = std::move(slots);
    nlohmann::ordered_json vars = nlohmann::ordered_json::object();
    for (size_t c = 0; c < g.variables.size(); ++c) {
      nlohmann::ordered_json row = nlohmann::ordered_json::array();
      for (size_t i = 0; i < g.slots.size(); ++i) {
        const size_t at_slot = c * g.slots.size() + i;
        row.push_back({{"value", g.now[at_slot] ? nlohmann::ordered_json(*g.now[at_slot]) : nullptr},
                       {"changed", g.changed(at_slot)}});
      }
      vars[g.variables[c]] = std::move(row);
    }
    j["vars"] = std::move(vars);
    nlohmann::ordered_json pins = nlohmann::ordered_json::array();
    for (const PinRow& p : g.pins) {
      nlohmann::ordered_json row = {{"text", p.text}};
      if (!p.error.empty()) row["error"] = p.error;
      else if (!p.truth) row["value"] = "not read yet";
      else
        row["value"] = *p.truth == watch::kUnknown ? nlohmann::ordered_json(nullptr)
                                                   : nlohmann::ordered_json(*p.truth == watch::kTrue);
      pins.push_back(std::move(row));
    }
    j["pins"] = std::move(pins);
  } else {
    j["error"] = std::string("no panel named ") + name + ": " + kPanelUsage;
  }
  return j;
}

}  // namespace dw::view
