// What the window shows of the session, read in one go between the worker's jobs (a Readout): the
// position, the watchpoints and their match steps, the interventions, the 3D scene of the current
// step, the selected module's inspector, the statistics, and the rows of the matches table. Panels
// draw only from a Readout, so they keep drawing while a job runs. Every text a panel shows comes
// from here too, which is what a script's `panel` command reads back.
#pragma once

#include <algorithm>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "app/view/view_model.h"
#include "render/scene.h"
#include "scenarios/scenario.h"
#include "sim/bookmarks.h"
#include "sim/session.h"
#include "watch/kleene.h"

namespace dw::view {

struct WatchRow {
  // Its name, reading and action (docs/design.md §7a, §4a), and its text as written (what the
  // edit box shows), not in normal form.
  sim::WatchSpec spec;
  int64_t lag = 0;
  uint64_t matches = 0;
  size_t slots = 0;
  std::vector<int64_t> nearest_steps;  // the match steps just before and after the current one: P and N
  std::vector<uint32_t> lane;          // matches per column of the timeline (Readout::timeline)
};

struct VariableRow {
  std::string name;
  int64_t value = 0;
  std::optional<int64_t> before;  // at the step before; nothing at step 0
  bool changed() const { return before && *before != value; }
};

struct MatchRowText {
  MatchRef ref;
  std::string watch;
  int64_t t = 0, detected = 0;
  std::string slots;  // "a=3 b=7 c=8"
};

// Another module's line in the Module plot: whose ("b=6") and its values.
struct PlotOverlay {
  std::string label;
  std::vector<int64_t> values;
};

struct Inspector {
  sim::ModuleId module = 0;
  bool present = false;
  std::vector<VariableRow> variables;
  std::vector<sim::ModuleId> neighbors;
  std::optional<sim::Pose> pose;
  // The matches holding the module (a few), each as the matches table shows it: which, its step,
  // its slots -- so that two matches of one step read apart.
  std::vector<MatchRowText> matches;
  size_t matches_total = 0;
  // The plotted variable (ViewModel::plot_variable) over steps [plot_from, plot_from + plot.size()):
  // the whole history read, in int64 (as floats, 19-digit values collapsed into one).
  int plot_column = 0;
  int64_t plot_from = 0;
  std::vector<int64_t> plot;
  // When the module fills a slot of the selected match: its slot ("a=7") and the group's other
  // modules' lines over the same steps, plotted with it (GroupSeries).
  std::string plot_label;
  std::vector<PlotOverlay> plot_group;
};

// A condition pinned in the Group tab (ViewModel::pins) and its truth on the group at the current
// step: true, false, unknown, or not read yet; or why it cannot be asked of this group.
struct PinRow {
  std::string text;
  std::string error;
  std::optional<watch::Truth> truth;
};

// The selected match's group side by side (the Group tab): a column per slot, a row per variable,
// whole values at the current step, marked where they changed since the step before.
struct GroupTable {
  MatchRef match;
  int64_t t = 0;                       // the match's step
  std::vector<std::string> slots;      // the slot names
  std::vector<sim::ModuleId> modules;  // filling them
  std::vector<std::string> variables;
  // [variable * slots + slot]: the current step's values and the step before's; nothing while a
  // module is absent, or the step before is not read yet (GroupWindow).
  std::vector<std::optional<int64_t>> now, before;
  std::vector<PinRow> pins;
  bool changed(size_t i) const { return now[i] && before[i] && *now[i] != *before[i]; }
};

struct StatsRow {  // one watchpoint's detector at one step
  int64_t step = 0;
  uint64_t live = 0, created = 0, messages = 0, matches = 0;
  double seconds = 0;
  std::vector<uint64_t> live_by_filled;
};

struct Readout {
  uint64_t version = 0;  // the worker's finished jobs when read
  Position at;
  int64_t decided = -1;
  std::vector<WatchRow> watches;
  std::vector<int64_t> intervention_steps;
  std::vector<sim::Bookmark> bookmarks;  // the shell's (`mark`), drawn on the timeline
  Timeline timeline;                     // the geometry the lanes were counted for
  int columns = 0;
  std::vector<std::string> interventions;  // one line each, as `interventions` answers
  render::Scene scene;
  bool physics = false;               // a Bullet world: its contacts can be drawn
  std::vector<int64_t> color_values;  // per module, the colour-by variable's value (the tooltip)
  std::optional<Inspector> inspector;
  std::optional<GroupTable> group;
  std::vector<std::vector<StatsRow>> stats;  // per watchpoint, the steps around the current one
  std::vector<MatchRowText> match_rows;
  size_t match_total = 0;
  size_t history_bytes = 0, keyframes = 0;
  int64_t keyframe_interval = 0;
  std::optional<sim::ProgramFailure> failure;  // what stopped the run, shown until it moves on

  // The panels' text, for scripts and tests: "matches" (rows), "inspector", "watchpoints",
  // "position".
  nlohmann::ordered_json panel(const std::string& name, const sim::Model& model) const;
};

// How much a Readout holds: table rows, the inspector's matches and plot, the statistics' steps.
struct ReadoutLimits {
  size_t match_rows = 10'000;
  size_t module_matches = 100;
  int64_t plot_steps = 1'000'000;  // the inspector's plot: this many steps ending at the latest
  int64_t stats_steps = 200;
};

// Every variable of one module over the steps up to the latest: the inspector's marks of what
// changed and its plot (the whole history, so that a seek need not read it again). Re-simulated
// from the keyframes (a job of its own, off the frame loop), never moving the session's cursor.
struct ModuleWindow {
  sim::ModuleId module = 0;
  int64_t from = 0, to = -1;
  size_t interventions = 0;   // the branch it was read on (a new intervention makes it stale)
  std::vector<int64_t> rows;  // (to - from + 1) rows of every variable
};
std::optional<ModuleWindow> read_module_window(sim::Session& session, sim::ModuleId m, int64_t steps,
                                               const sim::Control& control = {});
// True when `window` is module m's on the session's branch and holds its current step.
bool window_holds(const ModuleWindow& window, const sim::Session& session, sim::ModuleId m);

// What the Group tab reads off the frame loop, a job of its own (re-simulated from the keyframes):
// the group's values at the step before the current one and the pins' truths at the current one.
struct GroupWindow {
  std::vector<sim::ModuleId> modules;
  std::vector<std::string> slots, pins;
  int64_t t = -1, latest = -1;
  size_t interventions = 0;                    // the branch it was read on
  std::vector<std::optional<int64_t>> before;  // as GroupTable::before
  std::vector<PinRow> pin_rows;
  // True when it is `group`'s, with these pins, read at step t of the branch with `interventions`
  // whose latest step is `latest`.
  bool holds(int64_t at, int64_t latest_step, size_t branch_interventions, const GroupTable& group,
             const std::vector<std::string>& with_pins) const {
    return t == at && latest == latest_step && interventions == branch_interventions && modules == group.modules &&
           slots == group.slots && pins == with_pins;
  }
};
std::optional<GroupWindow> read_group_window(sim::Session& session, std::vector<sim::ModuleId> modules,
                                             std::vector<std::string> slots, std::vector<std::string> pins,
                                             const sim::Control& control = {});
// The selected match's group table (nothing without a selected match with slots), the step
// before's values and the pins' truths taken from `window` when it holds.
std::optional<GroupTable> read_group_table(sim::Session& session, const ViewModel& view, const GroupWindow* window);

// The plotted variable of the selected match's group over the inspector's steps (the Module plot's
// other lines), read by a job of its own as a ModuleWindow is, and kept across seeks.
struct GroupSeries {
  std::vector<sim::ModuleId> modules;
  int column = 0;
  int64_t from = 0, to = -1;
  size_t interventions = 0;                  // the branch it was read on
  std::vector<std::vector<int64_t>> values;  // per module, (to - from + 1) values
  bool holds(std::span<const sim::ModuleId> group, int at_column, int64_t latest, size_t branch_interventions) const {
    return std::ranges::equal(modules, group) && column == at_column && to == latest &&
           interventions == branch_interventions;
  }
};
std::optional<GroupSeries> read_group_series(sim::Session& session, std::vector<sim::ModuleId> modules, int column,
                                             int64_t steps, const sim::Control& control = {});

// What a Readout is read for besides the view model.
struct ReadoutRequest {
  uint64_t version = 0;  // the worker's finished jobs
  const ModuleWindow* window =
      nullptr;        // when it is the selected module's up to the current step: the inspector's history
  Timeline timeline;  // the timeline as drawn, and its width in pixels: the lanes
  int columns = 0;
  const Readout* keep_rows = nullptr;  // while playing: the matches table of this Readout stays (rows cost O(matches))
  const GroupWindow* group_window = nullptr;  // the Group tab's step before and pins
  const GroupSeries* group_series = nullptr;  // the Module plot's other lines
};

// Reads the session (which the caller must not share with a running job).
Readout read_readout(sim::Session& session, const scenarios::Scenario& scenario, const ViewModel& model,
                     const ReadoutRequest& request, const ReadoutLimits& limits = {});

// "a=3 b=7": a group's slots by name.
std::string slots_text(const sim::Session& session, uint32_t watch, std::span<const sim::ModuleId> group);

}  // namespace dw::view
