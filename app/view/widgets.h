// Small Dear ImGui helpers the panels share: text that fits its cell (or is visibly cut), widths
// that hold a label whole, rows that wrap. Used while a panel is drawn.
#pragma once

#include <imgui.h>

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
// A button's width for its label.
float button_width(const std::string& label);
// Puts the next widget, `width` wide, on the line of the last one when it fits there, else on the
// next line: rows of buttons wrap in a narrow window instead of running off its edge.
void flow(float width);
// The width left on the line for a field followed by small buttons with these labels.
float width_beside(std::initializer_list<const char*> buttons);
// The width a combo needs to show `text` whole: its arrow and padding besides.
float combo_width(const char* text);
// A combo as wide as its widest item.
float combo_width_of(std::span<const char* const> items);

}  // namespace dw::view
