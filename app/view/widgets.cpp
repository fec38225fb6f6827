// The panels' shared helpers (widgets.h), and how the debugger notes the widgets it draws, so
// that a window script can press and type into them as a person does (window_script.cpp).
#include "app/view/widgets.h"

#include <imgui_internal.h>  // the last item's flags: a disabled button cannot be pressed

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/view/debugger.h"

namespace dw::view {

ImU32 lane_color(size_t w) {
  static const ImU32 colors[] = {IM_COL32(230, 85, 60, 255), IM_COL32(70, 150, 230, 255), IM_COL32(90, 190, 90, 255),
                                 IM_COL32(220, 170, 40, 255), IM_COL32(170, 100, 220, 255)};
  return colors[w % std::size(colors)];
}

std::string fitted_text(const std::string& text, float room) {
  std::string shown = text;
  if (ImGui::CalcTextSize(text.c_str()).x > room) {
    while (shown.size() > 1 && ImGui::CalcTextSize((shown + "...").c_str()).x > room) shown.pop_back();
    shown += "...";
  }
  return shown;
}

bool cell_text(const std::string& text, std::optional<ImVec4> color) {
  const std::string shown = fitted_text(text, ImGui::GetContentRegionAvail().x);
  if (color) ImGui::TextColored(*color, "%s", shown.c_str());
  else ImGui::TextUnformatted(shown.c_str());
  if (shown != text && ImGui::IsItemHovered()) ImGui::SetTooltip("%s", text.c_str());
  return shown != text;
}

float names_width(const std::vector<std::string>& names, float least, float most) {
  float width = least;
  for (const std::string& n : names) width = std::max(width, ImGui::CalcTextSize(n.c_str()).x);
  return std::min(width + 2 * ImGui::GetStyle().CellPadding.x, most);
}

float width_beside(std::initializer_list<const char*> buttons) {
  const ImGuiStyle& style = ImGui::GetStyle();
  float width = ImGui::GetContentRegionAvail().x;
  for (const char* b : buttons) width -= ImGui::CalcTextSize(b).x + 2 * style.FramePadding.x + style.ItemSpacing.x;
  return std::max(60.0f, width);
}

float combo_width(const char* text) {
  return ImGui::CalcTextSize(text).x + ImGui::GetFrameHeight() + 2 * ImGui::GetStyle().FramePadding.x;
}

float combo_width_of(std::span<const char* const> items) {
  float width = 0;
  for (const char* item : items) width = std::max(width, combo_width(item));
  return width;
}

float button_width(const std::string& label) {
  return ImGui::CalcTextSize(label.c_str(), nullptr, true).x + 2 * ImGui::GetStyle().FramePadding.x;
}

namespace {

// Where v lies between lo and hi, 0 to 1, in exact integer differences (no int64 overflow).
double share_of(int64_t v, int64_t lo, int64_t hi) {
  return double(uint64_t(v) - uint64_t(lo)) / double(uint64_t(hi) - uint64_t(lo));
}

// Per pixel column of `columns`, the smallest and largest of its steps' values, and of the last
// value of the column before (the line joins them, as a step does).
std::vector<std::pair<int64_t, int64_t>> column_ranges(std::span<const int64_t> values, size_t columns) {
  std::vector<std::pair<int64_t, int64_t>> ranges(columns);
  const size_t n = values.size();
  for (size_t c = 0; c < columns; ++c) {
    const size_t first = c * n / columns, last = std::max(first + 1, (c + 1) * n / columns);
    auto [lo, hi] = std::minmax_element(values.begin() + std::ptrdiff_t(first), values.begin() + std::ptrdiff_t(last));
    ranges[c] = {*lo, *hi};
    if (first > 0) ranges[c] = {std::min(*lo, values[first - 1]), std::max(*hi, values[first - 1])};
  }
  return ranges;
}

}  // namespace

PlotDrawn history_plot(const std::string& title, std::span<const PlotSeries> lines, int64_t from, int64_t current,
                       float height) {
  ImGui::TextUnformatted(title.c_str());
  std::vector<PlotLabel> legend;
  if (lines.size() > 1)  // whose each line is, in its colour, after the title
    for (const PlotSeries& line : lines) {
      ImGui::SameLine();
      ImGui::PushStyleColor(ImGuiCol_Text, line.color);
      ImGui::TextUnformatted(line.label.c_str());
      ImGui::PopStyleColor();
      const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
      legend.push_back({line.label, {lo.x, lo.y, hi.x, hi.y}});
    }
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  const float width = ImGui::GetContentRegionAvail().x, line_height = ImGui::GetTextLineHeight();
  ImGui::Dummy(ImVec2(width, height + line_height));  // the plot, then the steps under it
  PlotDrawn drawn{{origin.x, origin.y, origin.x + width, origin.y + height}, std::move(legend)};
  const size_t n = lines.empty() ? 0 : lines[0].values.size();
  if (n == 0) return drawn;
  int64_t lo = lines[0].values[0], hi = lo;
  for (const PlotSeries& line : lines) {
    if (line.values.size() != n) continue;  // not drawn: a line must span the plot's steps
    const auto [lo_at, hi_at] = std::minmax_element(line.values.begin(), line.values.end());
    lo = std::min(lo, *lo_at), hi = std::max(hi, *hi_at);
  }
  const bool constant = lo == hi;
  const std::string hi_text = std::to_string(hi), lo_text = std::to_string(lo);
  const float axis = std::max(ImGui::CalcTextSize(hi_text.c_str()).x, ImGui::CalcTextSize(lo_text.c_str()).x) + 6;
  const ImVec2 p0(origin.x + axis, origin.y + line_height * 0.5f),
      p1(origin.x + width - 4, origin.y + height - line_height * 0.5f);
  drawn.area = {p0.x, p0.y, p1.x, p1.y};
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const ImU32 text = ImGui::GetColorU32(ImGuiCol_Text), faint = ImGui::GetColorU32(ImGuiCol_TextDisabled);
  draw->AddRectFilled(p0, p1, ImGui::GetColorU32(ImGuiCol_FrameBg));
  draw->AddLine(ImVec2(p0.x, p0.y), ImVec2(p0.x, p1.y), faint);
  draw->AddLine(ImVec2(p0.x, p1.y), ImVec2(p1.x, p1.y), faint);
  // Line i's offset from lines[0]: 0, -2, +2, -4, ... pixels; the margin inside the frame (3 pixels
  // for one line) keeps a line at either extreme whole over the axis. A constant across the middle
  // (along the bottom it read as the smallest value).
  auto offset_of = [](size_t i) { return float((i % 2 ? -2 : 2) * int((i + 1) / 2)); };
  const float margin = 3 + 2 * float(lines.size() / 2);
  auto y_of = [&](int64_t v) {
    const double share = constant ? 0.5 : share_of(v, lo, hi);
    return float(p1.y - margin - share * double(p1.y - p0.y - 2 * margin));
  };
  auto label = [&](const std::string& words, ImVec2 at, ImU32 color) {
    draw->AddText(at, color, words.c_str());
    const ImVec2 size = ImGui::CalcTextSize(words.c_str());
    drawn.labels.push_back({words, {at.x, at.y, at.x + size.x, at.y + size.y}});
  };
  label(hi_text, ImVec2(origin.x, y_of(hi) - line_height * 0.5f), text);
  if (!constant) label(lo_text, ImVec2(origin.x, y_of(lo) - line_height * 0.5f), text);
  const size_t columns = size_t(std::max(1.0f, p1.x - p0.x));
  auto x_of = [&](double i) { return p0.x + float(i / double(n)) * (p1.x - p0.x); };  // step i: [x_of(i), x_of(i+1)]
  if (current >= from && current < from + int64_t(n)) {
    const float x = x_of(double(current - from) + 0.5);
    draw->AddLine(ImVec2(x, p0.y), ImVec2(x, p1.y), IM_COL32(240, 200, 60, 200));
  }
  for (size_t i = lines.size(); i-- > 0;) {
    const PlotSeries& line = lines[i];
    if (line.values.size() != n) continue;
    const float dy = offset_of(i);
    auto y = [&](int64_t v) { return y_of(v) + dy; };
    if (n <= columns) {
      for (size_t s = 0; s < n; ++s) {
        const float at = y(line.values[s]);
        draw->AddLine(ImVec2(x_of(double(s)), at), ImVec2(x_of(double(s + 1)), at), line.color, 2);
        if (s + 1 < n && line.values[s + 1] != line.values[s])
          draw->AddLine(ImVec2(x_of(double(s + 1)), at), ImVec2(x_of(double(s + 1)), y(line.values[s + 1])), line.color,
                        2);
      }
    } else {
      const auto ranges = column_ranges(line.values, columns);
      for (size_t c = 0; c < columns; ++c) {
        const float x = p0.x + float(c);
        draw->AddRectFilled(ImVec2(x, y(ranges[c].second) - 1), ImVec2(x + 1, y(ranges[c].first) + 1), line.color);
      }
    }
  }
  label("step " + std::to_string(from), ImVec2(p0.x, p1.y + 2), faint);
  const std::string last = std::to_string(from + int64_t(n) - 1);
  if (n > 1) label(last, ImVec2(p1.x - ImGui::CalcTextSize(last.c_str()).x, p1.y + 2), faint);
  return drawn;
}

void flow(float width) {
  const float right = ImGui::GetItemRectMax().x + ImGui::GetStyle().ItemSpacing.x + width;
  if (right <= ImGui::GetWindowPos().x + ImGui::GetWindowContentRegionMax().x) ImGui::SameLine();
}

void Debugger::label_cell(const std::string& text, std::optional<ImVec4> color) {
  if (cell_text(text, color)) drawing_cut_labels_.push_back(text);
}

void Debugger::choice(const std::string& name, int& chosen, std::span<const char* const> items) {
  ImGui::SetNextItemWidth(combo_width_of(items));
  const bool open = ImGui::BeginCombo(("##" + name).c_str(), items[size_t(chosen)]);
  note_widget(name, combo_width(items[size_t(chosen)]));
  if (!open) return;
  // Each item under "NAME: ITEM", for `press` once the list is open.
  for (size_t i = 0; i < items.size(); ++i) {
    if (ImGui::Selectable(items[i], int(i) == chosen)) chosen = int(i);
    note_widget(name + ": " + items[i], 0, true);
  }
  ImGui::EndCombo();
}

void Debugger::note_widget(const std::string& name, float text_width, bool selectable) {
  ImVec2 min = ImGui::GetItemRectMin(), max = ImGui::GetItemRectMax();
  if (selectable) {  // ImGui spreads a selectable's frame half the item spacing past its text
    const ImVec2 spread{ImGui::GetStyle().ItemSpacing.x * 0.5f, ImGui::GetStyle().ItemSpacing.y * 0.5f};
    min = ImVec2(min.x + spread.x, min.y + spread.y);
    max = ImVec2(max.x - spread.x, max.y - spread.y);
  }
  // Where it may show: its panel's visible area, or its table cell's.
  const ImVec2 clip_min = ImGui::GetWindowDrawList()->GetClipRectMin(),
               clip_max = ImGui::GetWindowDrawList()->GetClipRectMax();
  WidgetPlace place{min.x, min.y, max.x, max.y};
  place.cut = min.x < clip_min.x - 0.5f || max.x > clip_max.x + 0.5f || text_width > max.x - min.x + 0.5f;
  place.out_of_sight = min.y < clip_min.y - 0.5f || max.y > clip_max.y + 0.5f;
  if (name == scroll_to_) {
    ImGui::SetScrollHereY(0.5f);
    scroll_to_.clear();
  }
  place.disabled = (GImGui->LastItemData.InFlags & ImGuiItemFlags_Disabled) != 0;
  drawing_widgets_.try_emplace(name, place);
}

void Debugger::headers_row(const std::string& table) {
  ImGui::TableNextRow(ImGuiTableRowFlags_Headers);
  const bool sortable = (ImGui::GetCurrentTable()->Flags & ImGuiTableFlags_Sortable) != 0;
  for (int c = 0; c < ImGui::TableGetColumnCount(); ++c) {
    if (!ImGui::TableSetColumnIndex(c)) continue;
    const char* name = ImGui::TableGetColumnName(c);
    // A sortable column keeps room for its arrow (ImGui clips a header silently: "matc", "detec").
    const float room = ImGui::GetContentRegionAvail().x, text_width = ImGui::CalcTextSize(name).x;
    const bool arrow = sortable && !(ImGui::TableGetColumnFlags(c) & ImGuiTableColumnFlags_NoSort);
    const bool cut = text_width + (arrow ? header_arrow_width() : 0) > room + 0.5f;
    if (cut) drawing_cut_labels_.push_back(name);
    const ImVec2 at = ImGui::GetCursorScreenPos();  // where its text starts
    ImGui::PushID(c);
    ImGui::TableHeader(name);
    ImGui::PopID();
    // Noted as the room its text has, for the tests that look at its pixels.
    if (*name != 0)
      drawing_widgets_.try_emplace(
          table + ": " + name,
          WidgetPlace{at.x, at.y, at.x + room, at.y + ImGui::GetTextLineHeight(), cut, false, false, text_width});
  }
}

float header_arrow_width() { return ImGui::GetFontSize() * 0.65f + ImGui::GetStyle().ItemInnerSpacing.x; }

float header_width(const char* name, bool sortable) {
  return ImGui::CalcTextSize(name).x + (sortable ? header_arrow_width() : 0) + 2;
}

bool Debugger::button(const std::string& label, bool small) {
  const bool pressed = small ? ImGui::SmallButton(label.c_str()) : ImGui::Button(label.c_str());
  // "edit##w1" is noted as "edit w1": the label shown, and the row it belongs to.
  const size_t id = label.find("##");
  note_widget(id == std::string::npos ? label : label.substr(0, id) + " " + label.substr(id + 2));
  return pressed;
}

}  // namespace dw::view
