// Two tabs beside the statistics for comparing steps: **marks**, the bookmarks (a note on the
// current step; a click on one goes there), drawn as flags on the timeline, and **diff**, what
// differs between another step and the current one (the session's `diff`), each module listed
// and ringed in the 3D view.
#include <imgui.h>

#include <cinttypes>
#include <cmath>

#include "app/view/debugger.h"
#include "app/view/widgets.h"

namespace dw::view {

void Debugger::marks_tab() {
  const int64_t t = readout_.at.current;
  if (t < 0) {
    ImGui::TextDisabled("no step yet to mark");
    return;
  }
  ImGui::SetNextItemWidth(std::max(
      120.0f, ImGui::GetContentRegionAvail().x - button_width("mark this step") - ImGui::GetStyle().ItemSpacing.x));
  ImGui::InputTextWithHint("##note", "a note on this step", mark_note_, sizeof mark_note_);
  note_widget("note");
  ImGui::SameLine();
  if (button("mark this step")) {
    apply({command::mark(t, mark_note_)});
    mark_note_[0] = 0;
  }
  if (readout_.bookmarks.empty()) ImGui::TextDisabled("no bookmarks: they show as flags on the timeline");
  for (const sim::Bookmark& b : readout_.bookmarks) {
    const std::string at = std::to_string(b.at);
    if (button("x##unmark " + at, true)) apply({command::unmark(b.at)});
    ImGui::SameLine();
    const std::string label = "step " + at + (b.note.empty() ? "" : ": " + b.note) + "##mark " + at;
    if (ImGui::Selectable(label.c_str(), b.at == t)) apply({command::seek(b.at)});
    note_widget("bookmark " + at, 0, true);
  }
}

// A flag each over the timeline's lanes (from `top`, `height` high); the one under the mouse.
const sim::Bookmark* Debugger::timeline_bookmarks(float top, float height) {
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const ImVec2 mouse = ImGui::GetIO().MousePos;
  const sim::Bookmark* hovered = nullptr;
  for (const sim::Bookmark& b : readout_.bookmarks) {
    if (b.at < timeline_.first || b.at > timeline_.last) continue;
    const float x = timeline_.x_of(b.at);
    draw->AddTriangleFilled(ImVec2(x - 6, top), ImVec2(x + 6, top), ImVec2(x, top + 9), kBookmark);
    draw->AddLine(ImVec2(x, top), ImVec2(x, top + height), kBookmark, 1);
    if (std::abs(mouse.x - x) <= 6 && mouse.y >= top && mouse.y <= top + height) hovered = &b;
  }
  return hovered;
}

void Debugger::diff_tab() {
  const int64_t t = readout_.at.current;
  ImGui::TextUnformatted("compare step");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(110);
  ImGui::InputInt("##diff step", &diff_step_);
  note_widget("diff-step");
  ImGui::SameLine();
  ImGui::Text("with this step (%" PRId64 ")", t);
  ImGui::SameLine();
  if (button("diff") && t >= 0) apply({command::diff(std::max(0, diff_step_), t)});
  if (!diff_) {
    ImGui::TextDisabled("which modules' variables, presence or neighbours differ between two steps");
    return;
  }
  const nlohmann::ordered_json& d = *diff_;
  const int64_t count = d.value("count", int64_t{0});
  ImGui::Text("%" PRId64 " modules differ between steps %" PRId64 " and %" PRId64 "%s", count, d.value("a", int64_t{0}),
              d.value("b", int64_t{0}), d.contains("more") ? " (the first 1000 below)" : "");
  ImGui::SameLine();
  if (button("clear", true)) {
    diff_.reset();
    return;
  }
  for (const auto& row : d["modules"]) {
    std::string what;
    if (row.contains("present")) what += row["present"][1].get<bool>() ? "arrives; " : "leaves; ";
    if (row.contains("vars"))
      for (const auto& [name, v] : row["vars"].items()) what += name + " " + v[0].dump() + " -> " + v[1].dump() + "; ";
    for (const char* key : {"gained", "lost"})
      if (row.contains(key))
        what += std::string(key == std::string_view("gained") ? "+" : "-") + "nbrs " + row[key].dump() + "; ";
    const std::string id = row["module"].dump();
    if (ImGui::Selectable(
            ("module " + id + ": " + what + "##diff " + id).c_str(),
            model_.selected && session_.model().universe.id(*model_.selected) == row["module"].get<uint32_t>())) {
      if (const auto m = module_of_id(session_.model().universe, row["module"].get<uint32_t>())) {
        model_.on_module_click(*m);
        readout_stale_ = true;
      }
    }
    note_widget("diff " + id, 0, true);
  }
}

// The modules the diff lists, ringed in the 3D view (whose picture's top left is at `origin`).
void Debugger::diff_in_view(ImVec2 origin, ImVec2 scale) {
  if (!diff_ || readout_.scene.modules.empty()) return;
  const glm::mat4 vp = renderer_->view_projection(camera_scene(), view_.width, view_.height);
  ImDrawList* draw = ImGui::GetWindowDrawList();
  for (const auto& row : (*diff_)["modules"])
    if (const auto p = module_on_screen(row["module"].get<uint32_t>(), vp, origin, scale))
      draw->AddCircle(*p, 9, kDiffRing, 20, 2.5f);
}

}  // namespace dw::view
