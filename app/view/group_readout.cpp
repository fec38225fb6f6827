// The Group tab's reading of the session: the selected match's group side by side at the current
// step (read with the Readout), and what needs the history (the step before's values, the pinned
// conditions' truths: sim/group_query.h; the group's lines in the Module plot), read by jobs of
// their own off the frame loop.
#include <algorithm>

#include "app/view/readout.h"
#include "sim/group_query.h"

namespace dw::view {
namespace {

// Each pin as a condition on the slots, asked of the group at the current step.
std::vector<PinRow> pin_rows(sim::Session& session, std::span<const sim::ModuleId> modules,
                             std::span<const std::string> slots, std::span<const std::string> pins,
                             const sim::Control& control, bool& cancelled) {
  std::vector<PinRow> rows;
  const int64_t t = session.current();
  for (const std::string& text : pins) {
    PinRow row{text, {}, std::nullopt};
    auto condition = sim::condition_on_slots(session.model(), slots, text);
    if (auto* error = std::get_if<std::string>(&condition)) {
      row.error = *error;
    } else if (t >= 0) {
      const auto truths =
          sim::truth_over(session, std::get<watch::Watchpoint>(condition).program, modules, t, t, control);
      if (!truths) {
        cancelled = true;
        return rows;
      }
      row.truth = truths->front();
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace

std::optional<GroupWindow> read_group_window(sim::Session& session, std::vector<sim::ModuleId> modules,
                                             std::vector<std::string> slots, std::vector<std::string> pins,
                                             const sim::Control& control) {
  GroupWindow w;
  w.t = session.current();
  w.latest = session.latest();
  w.interventions = session.interventions().size();
  const size_t v = session.model().variable_count(), k = modules.size();
  w.before.assign(v * k, std::nullopt);
  if (w.t >= 1)
    for (size_t slot = 0; slot < k; ++slot) {
      std::vector<uint8_t> present;
      const auto row = session.module_series(modules[slot], w.t - 1, w.t - 1, control, &present);
      if (!row) return std::nullopt;
      if (row->size() == v && present.front())
        for (size_t c = 0; c < v; ++c) w.before[c * k + slot] = (*row)[c];
    }
  bool cancelled = false;
  w.pin_rows = pin_rows(session, modules, slots, pins, control, cancelled);
  if (cancelled) return std::nullopt;
  w.modules = std::move(modules);
  w.slots = std::move(slots);
  w.pins = std::move(pins);
  return w;
}

std::optional<GroupSeries> read_group_series(sim::Session& session, std::vector<sim::ModuleId> modules, int column,
                                             int64_t steps, const sim::Control& control) {
  GroupSeries g;
  g.column = column;
  g.to = session.latest();
  g.interventions = session.interventions().size();
  g.from = std::max<int64_t>(0, g.to - steps + 1);
  if (g.to >= 0)
    for (sim::ModuleId m : modules) {
      auto values = session.series(m, column, g.from, g.to, control);
      if (!values) return std::nullopt;
      g.values.push_back(std::move(*values));
    }
  g.modules = std::move(modules);
  return g;
}

std::optional<GroupTable> read_group_table(sim::Session& session, const ViewModel& view, const GroupWindow* window) {
  const auto& chosen = view.selected_match;
  if (!chosen || chosen->watch >= session.watches().size() || chosen->index >= session.matches(chosen->watch).size())
    return std::nullopt;
  const watch::Program& program = session.watches()[chosen->watch].hosted.watchpoint.program;
  const size_t k = size_t(program.slot_count());
  if (k == 0) return std::nullopt;  // a zero-slot match has no group
  const sim::Model& model = session.model();
  const sim::MatchList& list = session.matches(chosen->watch);
  GroupTable g;
  g.match = *chosen;
  g.t = list.t[chosen->index];
  g.slots = program.slot_names;
  g.modules.assign(list.slots.begin() + std::ptrdiff_t(chosen->index * k),
                   list.slots.begin() + std::ptrdiff_t((chosen->index + 1) * k));
  g.variables = model.universe.variables;
  const size_t v = model.variable_count();
  g.now.assign(v * k, std::nullopt);
  g.before.assign(v * k, std::nullopt);
  if (session.current() >= 0) {
    const sim::State& s = session.state();
    const std::span<const uint8_t> present = session.seen_present();
    for (size_t slot = 0; slot < k; ++slot)
      if (present[g.modules[slot]])
        for (size_t c = 0; c < v; ++c) g.now[c * k + slot] = s.values[size_t{g.modules[slot]} * v + c];
  }
  if (window && window->holds(session.current(), session.latest(), session.interventions().size(), g, view.pins)) {
    g.before = window->before;
    g.pins = window->pin_rows;
  } else {
    for (const std::string& p : view.pins) g.pins.push_back({p, {}, std::nullopt});
  }
  return g;
}

}  // namespace dw::view
