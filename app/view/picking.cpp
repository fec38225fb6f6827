// Which module is under the mouse in the 3D view (render/picking.h, through the camera): a click
// selects it, a hover names it in a tooltip; a drag is the camera's (camera.cpp). And the other
// way: where a module shows, for what is drawn over the view (the Why panel's cone, a diff).
#include <imgui.h>

#include <algorithm>

#include "app/view/debugger.h"
#include "render/annotations.h"
#include "render/picking.h"

namespace dw::view {

std::optional<sim::ModuleId> module_of_id(const watch::Universe& universe, uint32_t id) {
  const auto& ids = universe.module_ids;
  if (ids.empty()) return id;
  const auto it = std::find(ids.begin(), ids.end(), id);
  if (it == ids.end()) return std::nullopt;
  return sim::ModuleId(it - ids.begin());
}

std::optional<ImVec2> Debugger::module_on_screen(uint32_t id, const glm::mat4& vp, ImVec2 origin, ImVec2 scale) const {
  const std::optional<sim::ModuleId> m = module_of_id(session_.model().universe, id);
  if (!m) return std::nullopt;
  const auto& modules = readout_.scene.modules;  // by id
  const auto s = std::lower_bound(modules.begin(), modules.end(), *m,
                                  [](const render::SceneModule& a, sim::ModuleId b) { return a.id < b; });
  if (s == modules.end() || s->id != *m) return std::nullopt;
  const auto p =
      render::project(vp, {s->pose.position[0], s->pose.position[1], s->pose.position[2]}, view_.width, view_.height);
  if (!p) return std::nullopt;
  return ImVec2(origin.x + p->x / scale.x, origin.y + p->y / scale.y);
}

std::optional<sim::ModuleId> Debugger::module_at(float x, float y) {
  const glm::mat4 vp = renderer_->view_projection(camera_scene(), view_.width, view_.height);
  return render::pick(readout_.scene, vp, view_.width, view_.height, {x, y});
}

void Debugger::view_input(float x, float y, bool hovered) {
  if (steer_camera(hovered)) {  // a click, not the end of a drag
    model_.on_module_click(module_at(x, y));
    readout_stale_ = true;
  }

  hovered_.reset();
  if (hovered && !dragging_) hovered_ = module_at(x, y);
  if (hovered_) {
    const sim::Model& m = session_.model();
    ImGui::BeginTooltip();
    ImGui::Text("module %u", m.universe.id(*hovered_));
    if (!readout_.color_values.empty() && *hovered_ < readout_.color_values.size())
      ImGui::Text("%s = %lld", model_.color_by.c_str(), static_cast<long long>(readout_.color_values[*hovered_]));
    ImGui::TextDisabled("click to select");
    ImGui::EndTooltip();
  }
}

}  // namespace dw::view
