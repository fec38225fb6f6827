// The Group tab, beside the statistics: the selected match's group side by side (a column per
// slot, a row per variable, whole values, those changed since the step before marked), and
// conditions in the watch language pinned over the slots' names (`a._priority > c._priority`),
// each decided on the group at every step shown, with buttons that go back and on to the nearest
// step where it holds (the session's `find`, rr's reverse-continue to a watchpoint).
#include <imgui.h>

#include <algorithm>
#include <cinttypes>

#include "app/view/debugger.h"
#include "app/view/widgets.h"
#include "sim/group_query.h"

namespace dw::view {
namespace {

const ImVec4 kChanged(1, 0.8f, 0.2f, 1);  // as the Module panel's variables
const ImVec4 kHolds(0.4f, 0.9f, 0.4f, 1);
const ImVec4 kUnknown(0.95f, 0.75f, 0.3f, 1);
const ImVec4 kMistake(1, 0.45f, 0.4f, 1);

}  // namespace

void Debugger::group_tab() {
  if (!readout_.group) {
    ImGui::TextWrapped("Choose a match (a row of Matches, or N and P) to see its group side by side here.");
    return;
  }
  const GroupTable& g = *readout_.group;
  const sim::Model& m = session_.model();
  const std::string& watch = readout_.watches[g.match.watch].spec.name;
  ImGui::Text("%s at t=%" PRId64, watch.c_str(), g.t);
  if (g.t != readout_.at.current) {
    ImGui::SameLine();
    ImGui::TextDisabled("(its values at step %" PRId64 ")", readout_.at.current);
  }
  const size_t k = g.slots.size();
  // A column per slot, as wide as its widest value: whole, so that a's and c's can be compared.
  std::vector<std::string> headers;
  std::vector<float> widths;
  for (size_t i = 0; i < k; ++i) {
    headers.push_back(g.slots[i] + "=" + std::to_string(m.universe.id(g.modules[i])));
    float w = header_width(headers.back().c_str());
    for (size_t c = 0; c < g.variables.size(); ++c)
      if (g.now[c * k + i]) w = std::max(w, ImGui::CalcTextSize((std::to_string(*g.now[c * k + i]) + " *").c_str()).x);
    widths.push_back(w);
  }
  // Every row and the horizontal scroll bar, when the panel has room (its values cut the last row).
  const float table_height =
      ImGui::GetTextLineHeightWithSpacing() * float(g.variables.size() + 1) + 8 + ImGui::GetStyle().ScrollbarSize;
  const float room = ImGui::GetContentRegionAvail().y - 3 * ImGui::GetFrameHeightWithSpacing();
  if (ImGui::BeginTable(
          "group", int(k) + 1,
          ImGuiTableFlags_RowBg | ImGuiTableFlags_Borders | ImGuiTableFlags_ScrollX | ImGuiTableFlags_ScrollY,
          ImVec2(0, std::clamp(table_height, ImGui::GetTextLineHeightWithSpacing() * 2, std::max(room, 40.0f))))) {
    ImGui::TableSetupScrollFreeze(1, 1);
    ImGui::TableSetupColumn("variable", ImGuiTableColumnFlags_WidthFixed, names_width(g.variables, 40, 200));
    for (size_t i = 0; i < k; ++i)
      ImGui::TableSetupColumn(headers[i].c_str(), ImGuiTableColumnFlags_WidthFixed, widths[i]);
    headers_row("group");
    for (size_t c = 0; c < g.variables.size(); ++c) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      label_cell(g.variables[c]);
      for (size_t i = 0; i < k; ++i) {
        ImGui::TableNextColumn();
        const size_t at = c * k + i;
        if (!g.now[at]) ImGui::TextDisabled("absent");
        else if (g.changed(at)) label_cell(std::to_string(*g.now[at]) + " *", kChanged);
        else label_cell(std::to_string(*g.now[at]));
        if (g.changed(at) && ImGui::IsItemHovered()) ImGui::SetTooltip("%" PRId64 " at the step before", *g.before[at]);
      }
    }
    ImGui::EndTable();
  }
  pins_rows(g);
}

// A field to pin a condition, then a row per pin: its truth at the current step, its text, and
// buttons to the nearest step back or on where it holds, and to unpin it.
void Debugger::pins_rows(const GroupTable& g) {
  const sim::Model& m = session_.model();
  ImGui::SetNextItemWidth(
      std::max(120.0f, ImGui::GetContentRegionAvail().x - button_width("pin") - ImGui::GetStyle().ItemSpacing.x));
  const bool entered = ImGui::InputTextWithHint("##pin", "pin a condition: a.x > b.x", pin_text_, sizeof pin_text_,
                                                ImGuiInputTextFlags_EnterReturnsTrue);
  note_widget("condition");
  ImGui::SameLine();
  if ((button("pin") || entered) && pin_text_[0] != 0) {
    // Checked here against this group's slots, so that a mistake is said where it was typed.
    auto condition = sim::condition_on_slots(m, g.slots, pin_text_);
    if (auto* error = std::get_if<std::string>(&condition)) {
      pin_error_ = *error;
    } else if (std::find(model_.pins.begin(), model_.pins.end(), pin_text_) == model_.pins.end()) {
      model_.pins.emplace_back(pin_text_);
      pin_text_[0] = 0;
      pin_error_.clear();
      readout_stale_ = true;
    }
  }
  if (!pin_error_.empty()) ImGui::TextColored(kMistake, "%s", pin_error_.c_str());
  for (size_t i = 0; i < g.pins.size(); ++i) {
    const PinRow& p = g.pins[i];
    const std::string n = std::to_string(i);
    if (!p.error.empty()) ImGui::TextColored(kMistake, "%-7s", "error");
    else if (!p.truth) ImGui::TextDisabled("%-7s", "...");
    else if (*p.truth == watch::kTrue) ImGui::TextColored(kHolds, "%-7s", "true");
    else if (*p.truth == watch::kFalse) ImGui::TextDisabled("%-7s", "false");
    else ImGui::TextColored(kUnknown, "%-7s", "unknown");
    if (!p.error.empty() && ImGui::IsItemHovered()) ImGui::SetTooltip("%s", p.error.c_str());
    ImGui::SameLine();
    const bool searchable = p.error.empty();
    if (!searchable) ImGui::BeginDisabled();
    if (button("<##holds " + n, true)) apply({command::find_holding(g.modules, g.slots, p.text, true)});
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("the nearest step before this one where it holds");
    ImGui::SameLine();
    if (button(">##holds " + n, true)) apply({command::find_holding(g.modules, g.slots, p.text, false)});
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("the nearest step after this one where it holds");
    if (!searchable) ImGui::EndDisabled();
    ImGui::SameLine();
    if (button("x##unpin " + n, true)) {
      model_.pins.erase(model_.pins.begin() + std::ptrdiff_t(i));
      readout_stale_ = true;
      break;
    }
    ImGui::SameLine();
    ImGui::TextUnformatted(p.text.c_str());
  }
}

}  // namespace dw::view
