// Small Dear ImGui helpers the panels share: text that fits its cell (or is visibly cut), widths
// that hold a label whole, rows that wrap. Used while a panel is drawn.
#pragma once

#include <imgui.h>

#include <array>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace dw::view {

// The colour of watchpoint w's timeline lane and name (w modulo their count).
ImU32 lane_color(size_t w);

// `text` as it fits in `room` pixels: whole, or cut with "...".
std::string fitted_text(const std::string& text, float room);
// A value in a table cell: whole when it fits, else cut at the right with "..." and whole in a
// tooltip, so that a cut number never reads as another number (ImGui clips a cell's text
// silently: 8280827919719202833 showed as 828082791971920283). True when it had to be cut.
bool cell_text(const std::string& text, std::optional<ImVec4> color = std::nullopt);
// The width of a table column that shows each of `names` whole (within `most` pixels).
float names_width(const std::vector<std::string>& names, float least, float most);
// The width a sorted table's header arrow takes beside its name.
float header_arrow_width();
// A table column's least width to show its header `name` whole (with its sort arrow if sortable).
float header_width(const char* name, bool sortable = false);
// A button's width for its label.
float button_width(const std::string& label);
// Puts the next widget, `width` wide, on the line of the last one when it fits there, else on the
// next line: rows of buttons wrap in a narrow window instead of running off its edge.
void flow(float width);
// The width left on the line for a field followed by small buttons with these labels.
float width_beside(std::initializer_list<const char*> buttons);
// The width a combo needs to show `text` whole: its arrow and padding besides.
float combo_width(const char* text);
// The colour of a history plot's line (history_plot).
constexpr ImU32 kPlotLineColor = IM_COL32(130, 200, 250, 255);
// A bookmark's flag on the timeline.
constexpr ImU32 kBookmark = IM_COL32(250, 220, 70, 255);
// The rings of the modules a diff of two steps lists, in the 3D view.
constexpr ImU32 kDiffRing = IM_COL32(80, 220, 240, 255);
// A text a plot wrote and where (for scripts and tests that look at it).
struct PlotLabel {
  std::string text;
  std::array<float, 4> rect;  // x0, y0, x1, y1
};
struct PlotDrawn {
  std::array<float, 4> area;  // the plot's frame: x0, y0, x1, y1
  std::vector<PlotLabel> labels;
};
// One line of a history plot: whose it is (empty for a lone line; "a=7" for a group's slot) and
// its values, one per step from the plot's first.
struct PlotSeries {
  std::string label;
  std::span<const int64_t> values;
  ImU32 color = kPlotLineColor;
};
// The colours of a group's lines after the selected module's (kPlotLineColor), in slot order.
constexpr std::array<ImU32, 4> kPlotOverlayColors = {IM_COL32(250, 150, 60, 255), IM_COL32(120, 220, 110, 255),
                                                     IM_COL32(235, 110, 210, 255), IM_COL32(200, 190, 255, 255)};
// A variable's history that tells the truth: its title above it, never over the line; axes with
// the largest and smallest values written whole at their heights (int64 to the pixel: as floats,
// 19-digit values collapsed into one) and the first and last steps under them; a step per value
// (a 0/1 variable reads as steps, not a ramp); a constant drawn across the middle with its value
// beside it; the current step marked. More steps than pixel columns are drawn honestly: each
// column spans its steps' smallest to largest value, so that a one-step spike still shows.
// Several lines (a group's modules) share the axes, each in its colour and named after the title;
// lines[0] is drawn last, on top, and the others 2 pixels apart from it and from each other, so
// that equal values still show every line. `from` is the step of each line's first value; `height`
// the plot's, the steps' line under it besides.
PlotDrawn history_plot(const std::string& title, std::span<const PlotSeries> lines, int64_t from, int64_t current,
                       float height);
// A combo as wide as its widest item.
float combo_width_of(std::span<const char* const> items);

}  // namespace dw::view
