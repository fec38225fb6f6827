// The panels' shared helpers (widgets.h), and how the debugger notes the widgets it draws, so
// that a window script can press and type into them as a person does (window_script.cpp).
#include "app/view/widgets.h"

#include <imgui_internal.h>  // the last item's flags: a disabled button cannot be pressed

#include <algorithm>

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

bool Debugger::button(const std::string& label, bool small) {
  const bool pressed = small ? ImGui::SmallButton(label.c_str()) : ImGui::Button(label.c_str());
  // "edit##w1" is noted as "edit w1": the label shown, and the row it belongs to.
  const size_t id = label.find("##");
  note_widget(id == std::string::npos ? label : label.substr(0, id) + " " + label.substr(id + 2));
  return pressed;
}

}  // namespace dw::view
