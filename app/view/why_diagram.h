// The Why panel's space-time diagram (docs/design.md §7b, in the style of ShiViz), read from the
// session's `why` answer: a column per module of the cone (the group's modules first, then the
// values asked for, then the rest by id), steps downward, a dot per event (filled where it
// changed a variable), an arrow per message from (sender, step sent) to (receiver, step read),
// and a dashed link where a cause runs through events the narrow cone dropped. The panel only
// draws this; the answer is the session's. Kept apart from any window, so that tests check it.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace dw::view {

struct WhyDot {
  size_t event = 0;  // its index in the answer's events
  int column = 0;
  int64_t step = 0;
  uint32_t module = 0;   // its id, as the answer gives it
  std::string writer;    // program, action, intervention, event, initial
  bool changed = false;  // some variable changed
  bool origin = false;   // the origin of a value asked for
  bool group = false;    // a module of the match's group
  std::string text;      // what a hover shows: who, when, what changed (old -> new), its causes
};

struct WhyArrow {
  int from_column = 0, to_column = 0;
  int64_t sent = 0, read = 0;
  bool message = true;  // false: a cause through dropped events (the narrow cone), drawn dashed
  bool is_new = true;   // a message not the same as a step before (the narrow cone keeps only these)
  std::string text;     // what a hover shows: from, to, steps and words
};

struct WhyDiagram {
  std::string command;             // the line that asked
  std::string title;               // "isLeader of 7 = 1 at step 1: written by its program at step 1"
  std::vector<uint32_t> modules;   // the columns, by module id
  std::vector<bool> group_column;  // the group's modules (a match's), or the values' modules
  int64_t first = 0, last = 0;     // the steps shown
  std::vector<WhyDot> dots;
  std::vector<WhyArrow> arrows;
  int64_t asked_at = 0;  // the session's current step when it answered
};

// The diagram of a `why` answer; nothing when it is not one.
std::optional<WhyDiagram> why_diagram(const nlohmann::ordered_json& answer, const std::string& command);

// Where the diagram's steps and columns go in the panel: its frame [x0, x0 + width) x [y0, y0 +
// height) below the column names and right of the step numbers, scrolled and zoomed as the
// timeline is (the wheel zooms the steps about the mouse, a right drag pans, `fit` goes back).
struct WhyView {
  static constexpr float kMinColumn = 44, kMaxColumn = 110, kMinStep = 28, kMaxStep = 160;
  bool fitted = true;
  float column_width = kMinColumn, step_height = kMinStep;
  float scroll_x = 0, scroll_y = 0;  // pixels of the diagram scrolled off the top left

  // Fitted: the whole diagram in the frame when it fits, each column and step at least the least.
  void fit(const WhyDiagram& diagram, float width, float height);
  // The steps' scale times `factor` keeping the point at y (frame pixels from its top) in place.
  void zoom(float factor, float y);
  void pan(float dx, float dy);
  // Scrolling kept within the diagram.
  void clamp(const WhyDiagram& diagram, float width, float height);
  // The centre of column c and the row of step t, in frame pixels.
  float x_of(int column) const { return (float(column) + 0.5f) * column_width - scroll_x; }
  float y_of(int64_t t, int64_t first) const { return (float(t - first) + 0.5f) * step_height - scroll_y; }
};

// The distance from point (px, py) to the segment (ax, ay)-(bx, by): a hover over an arrow.
float distance_to_segment(float px, float py, float ax, float ay, float bx, float by);

}  // namespace dw::view
