// Which module is under the mouse in the 3D view (render/picking.h, through the camera): a click
// selects it, a hover names it in a tooltip; a drag is the camera's (camera.cpp).
#include <imgui.h>

#include "app/view/debugger.h"
#include "render/picking.h"

namespace dw::view {

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
