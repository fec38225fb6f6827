// The debugger window's state and the commands its widgets send (issue: `dwatch view`), kept
// apart from any window so that tests drive it without one: the camera the user owns, the
// selection, the timeline's mapping of pixels to steps, the matches table's filter and order, and
// what each key does. The window (debugger.cpp) only draws this state and forwards input; the
// session (sim/session.h) decides everything about time. Commands are lines of the session
// language (docs/design.md §7a), so a widget, a key and a script line take the same path.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "render/camera.h"
#include "sim/session.h"
#include "watch/diagnostic.h"

namespace dw::view {

// A camera orbiting a target: yaw about the vertical (z) axis from +x, pitch above the horizon.
// Dragging orbits and pans, the wheel zooms; `F` fits the ensemble, `Z` centres the selection.
struct OrbitCamera {
  glm::vec3 target{0};
  float yaw = 0, pitch = 0.5f, distance = 10;

  // The orbit that sees what `camera` sees.
  static OrbitCamera looking(const render::Camera& camera);
  glm::vec3 eye() const;
  render::Camera camera() const;

  // Turns by the mouse's move in pixels (a full turn per 630 pixels); the pitch stays within
  // ±89 degrees so that up stays up.
  void orbit(float dx, float dy);
  // Moves the target across the view so that the scene follows the mouse: `view_height` pixels
  // cover the field of view at the target's distance.
  void pan(float dx, float dy, int view_height);
  // Closer by 10% per wheel notch (farther for negative ones), never through the target.
  void zoom(float notches);
};

// The timeline under the transport bar: steps first..last spread over [x0, x0 + width) pixels.
struct Timeline {
  int64_t first = 0, last = 0;
  float x0 = 0, width = 1;
  // The step drawn at pixel x (clamped into the timeline).
  int64_t step_at(float x) const;
  // The middle of step t's span of pixels.
  float x_of(int64_t t) const;
};

// Matches per pixel column of a watchpoint's lane: `steps` are its matches' steps, sorted.
std::vector<uint32_t> lane_density(std::span<const int64_t> steps, const Timeline& timeline, int columns);

// The first match step after t, and the last before it, in sorted match steps.
std::optional<int64_t> next_match(std::span<const int64_t> steps, int64_t t);
std::optional<int64_t> previous_match(std::span<const int64_t> steps, int64_t t);

// One match of one watchpoint, by its index in the session's list.
struct MatchRef {
  uint32_t watch = 0;
  size_t index = 0;
  bool operator==(const MatchRef&) const = default;
};

// The matches table's filter and order.
struct MatchFilter {
  int watch = -1;                       // -1: every watchpoint
  std::optional<sim::ModuleId> module;  // only groups holding this module
  enum class Order { Step, Watch, Detected } order = Order::Step;
  bool descending = false;
};

// The matches the table lists, at most `limit` of them (the table says how many were left out).
struct MatchRows {
  std::vector<MatchRef> rows;
  size_t total = 0;  // before the limit
};
MatchRows filter_matches(const sim::Session& session, const MatchFilter& filter, size_t limit);

// The keys the window binds (F1 lists them).
enum class Key { Space, Right, Left, N, P, F, Z, Y, T, I, C, Home, End, F1, F12, Escape };
std::optional<Key> key_named(std::string_view name);
// "key NAME: one of space, right, ...": every name key_named knows, for the mistake.
std::string key_usage();
struct KeyHelp {
  std::string_view keys, what;
};
const std::vector<KeyHelp>& key_help();

// A script's words, with where each stands in the script.
struct ScriptWord {
  std::string text;
  watch::Span span;
};
// The commands only the window has (docs/design.md §7a): click M | click match ROW | click timeline T,
// key NAME, wait N, screenshot FILE, panel NAME.
bool is_window_command(std::string_view word);
// What `panel` reads, said when it names none of them.
inline constexpr const char* kPanelUsage =
    "panel NAME: position, matches, watchpoints, inspector, group, plots, timeline, widgets, pointers or why";
// A mistake in one (its words, the span just past the line's end), or nothing.
std::optional<watch::Diagnostic> check_window_command(std::span<const ScriptWord> words, uint32_t module_count,
                                                      watch::Span end_of_line);

// A session command's answer said in words for the status line ("paused at step 1 on
// two_leaders: a=7 b=6 c=17, 91 matches at that step"), rather than its JSON.
std::string answer_words(const nlohmann::ordered_json& answer);
// Where the cursor stands among the simulated steps, said one way everywhere (the status line and
// the position line said "step 0 of 3 simulated" beside "at step 0 of 4 simulated"): "step 1 (0 to
// 3 simulated)".
std::string position_words(int64_t current, int64_t latest);
// "1 intervention", "2 interventions".
std::string counted(int64_t n, const std::string& one);

// Where the session is, as the window last read it.
struct Position {
  int64_t current = -1, latest = -1, end = 0;
};

// The steps the timeline shows. Fitted, it follows what exists: step 0 to a little past the latest
// (never the scenario's whole length while a few steps are simulated: the marks would crowd into
// a few pixels). The wheel zooms about the step under the mouse, a drag with the right button pans,
// and "fit" goes back; the range stays within step 0 and the scenario's end (or the latest, past it).
struct TimelineRange {
  static constexpr int64_t kMinSpan = 8;  // steps shown at the deepest zoom
  bool fitted = true;
  int64_t first = 0, last = 0;  // when not fitted
  // [first, last] to draw at this position.
  std::pair<int64_t, int64_t> shown(const Position& at) const;
  // Zooms by `factor` (< 1 in, > 1 out) keeping step `about` under the same pixel.
  void zoom(double factor, int64_t about, const Position& at);
  // Moves the range by `steps` (negative: towards step 0).
  void pan(int64_t steps, const Position& at);
  // Shows [first, last] (clamped, at least kMinSpan steps when there are as many).
  void show(int64_t first, int64_t last, const Position& at);
  void fit() { fitted = true; }
};

// Where the window's panels go: the 3D view at the top left, the transport bar and timeline under
// it, and a column on the right of Watchpoints (with the editor), Matches, Module and Statistics.
// The column and the bar keep the sizes their contents need; the 3D view takes what is left. Laid
// out again whenever the window's size changes; below kMinWidth x kMinHeight the panels no longer
// hold their contents, which the window says.
struct PanelRect {
  float x = 0, y = 0, width = 0, height = 0;
};
struct PanelLayout {
  static constexpr float kMinWidth = 1024, kMinHeight = 640;
  PanelRect view, transport, watchpoints, matches, module, statistics;
  PanelRect why;  // while the Why panel is open: the right part of the 3D view's place
  bool too_small = false;
};
// `lanes`: the timeline's (one a watchpoint, and the interventions'), which the transport bar holds;
// `why`: the Why panel is open, beside the 3D view; `tall_tabs`: the Statistics panel shows its
// group, marks or diff tab, which take more of the column.
PanelLayout panel_layout(float x, float y, float width, float height, int lanes = 2, bool why = false,
                         bool tall_tabs = false);

// Lines of the session language that the widgets send.
namespace command {
std::string step(int64_t n);
std::string run();
std::string run_to(int64_t t);                     // runs until step t is current (or a pause)
std::string continue_run();                        // on past the pause that stopped the cursor
std::string run_to_match(std::string_view watch);  // on to the watchpoint's next match (or a pause)
std::string action(std::string_view watch, sim::MatchAction action);
std::string seek(int64_t t);
std::string set(sim::ModuleId m, std::string_view variable, int64_t value);
std::string remove(sim::ModuleId m);
std::string push(sim::ModuleId m, glm::vec3 impulse);
// `options`: the algorithm and action words ("distributed pause"), or empty for the defaults.
std::string watch(std::string_view name, std::string_view options, std::string_view text);
std::string unwatch(std::string_view name);
std::string reload();
std::string save(const std::string& file, bool overwrite);
std::string record(const std::string& file);
// find prev|next M VAR: the nearest step where it changed.
std::string find_change(sim::ModuleId m, std::string_view variable, bool back);
// find prev|next M... when modules(SLOTS); EXPRESSION: the nearest step where a pin holds.
std::string find_holding(std::span<const sim::ModuleId> group, std::span<const std::string> slots,
                         std::string_view expression, bool back);
std::string mark(int64_t t, std::string_view note);
std::string unmark(int64_t t);
std::string diff(int64_t a, int64_t b);
}  // namespace command

class ViewModel {
 public:
  // What the window shows and the user chose.
  std::optional<sim::ModuleId> selected;
  std::optional<MatchRef> selected_match;
  OrbitCamera camera;
  bool camera_placed = false;  // false: fit the camera to the ensemble at the next frame
  bool playing = false;
  int speed = 10;  // steps per second while playing; 0: as fast as the session steps
  int chosen_watch = 0;
  TimelineRange timeline_range;
  MatchFilter filter;
  std::string color_by;
  std::string plot_variable;  // the inspector's plot; empty: the first variable
  // Conditions pinned in the Group tab, over the selected match's slot names (a._priority >
  // c._priority), each decided on its group at every step shown.
  std::vector<std::string> pins;
  bool show_help = false;
  // The module the camera follows (`T`, the script's `follow M`): each frame its target is the
  // module's centre, the camera's turn and distance kept. Nothing: the camera stays where it is.
  std::optional<sim::ModuleId> followed;
  // Seeing inside (render::Scene::isolate, cut): only the groups and the selection (`I`), and the
  // modules on this side of a plane across axis cut_axis (-1: none) at cut_at.
  bool isolate = false;
  int cut_axis = -1;
  float cut_at = 0;
  // The physics' contact points and normals over the view (render::Scene::contacts; `C`).
  bool contacts = false;

  // What a key does: the commands to send (in order) and what changes here. `chosen_steps` are
  // the chosen watchpoint's match steps (for N and P); with no match known after the current step,
  // N runs on to the next match of `chosen_watch` (named).
  std::vector<std::string> on_key(Key key, const Position& at, std::span<const int64_t> chosen_steps,
                                  std::string_view chosen_watch = {});
  // A click on the timeline at pixel x.
  std::vector<std::string> on_timeline_click(const Timeline& timeline, float x, const Position& at);
  // A click on a row of the matches table: go to its step, select the group and its first slot.
  std::vector<std::string> on_match_click(const sim::Session& session, MatchRef match);
  // A click in the 3D view on a module, or on nothing (clears the selection).
  void on_module_click(std::optional<sim::ModuleId> module);
  // Playing at `speed`: how many steps to ask for after `seconds` since the last request.
  int64_t steps_due(double seconds) const;

  // Set by `F1` and `F12` for the window to act on (it owns the file and the help window).
  bool screenshot_requested = false;
  bool focus_selection = false;  // `Z`: the window centres the camera on the selection
  // A pause, or a match chosen: the window makes sure its group shows, moving the camera only when
  // some of it is out of view, and then to the whole ensemble (centring on a group at the edge of
  // the lattice cut the rest of it off).
  bool reveal_group = false;
};

}  // namespace dw::view
