// The 3D view's camera: where it looks (OrbitCamera, view_model.h), fitted to the ensemble, zoomed
// onto the selection (and its group) or moved back to show a match's group; turned, panned and
// zoomed by the mouse.
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "app/view/debugger.h"
#include "render/annotations.h"

namespace dw::view {

std::string vec_text(glm::vec3 v) {
  std::ostringstream s;
  s.imbue(std::locale::classic());
  s.precision(6);
  s << v.x << "," << v.y << "," << v.z;
  return s.str();
}

render::Scene& Debugger::camera_scene() {
  const render::Camera c = model_.camera.camera();
  readout_.scene.camera_eye = sim::Vec3{c.eye.x, c.eye.y, c.eye.z};
  readout_.scene.camera_target = sim::Vec3{c.target.x, c.target.y, c.target.z};
  return readout_.scene;
}

void Debugger::place_camera() {
  if (view_.width < 16 || view_.height < 16 || readout_.scene.modules.empty()) return;
  window_.make_current();
  model_.camera = OrbitCamera::looking(renderer_->fitted_camera(readout_.scene, view_.width, view_.height));
  model_.camera_placed = true;
}

void Debugger::focus_on_selection() {
  model_.focus_selection = false;
  if (!model_.selected) return;
  // The selected module, with the group it belongs to when it is one of the shown group's: Z zooms
  // so that they fill about 40% of the view's height (it used to pan only, and among 11,000
  // modules a group stayed 20 pixels wide).
  bool in_group = false;
  for (const render::SceneModule& m : readout_.scene.modules) in_group = in_group || (m.selected && m.highlighted);
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const render::SceneModule& m : readout_.scene.modules)
    if (m.selected || (in_group && m.highlighted)) {
      const glm::vec3 p(m.pose.position[0], m.pose.position[1], m.pose.position[2]);
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
  if (lo.x > hi.x) return;
  const float radius = glm::length(hi - lo) * 0.5f + 0.7f;  // a module's half diagonal besides
  model_.camera.target = (lo + hi) * 0.5f;
  model_.camera.distance = radius / (0.4f * std::tan(render::Camera{}.fov_y * 0.5f));
}

int Debugger::modules_in_view(std::span<const sim::ModuleId> modules) {
  window_.make_current();
  const glm::mat4 vp = renderer_->view_projection(camera_scene(), view_.width, view_.height);
  int inside = 0;
  for (const render::SceneModule& m : readout_.scene.modules) {
    if (!modules.empty() && std::find(modules.begin(), modules.end(), m.id) == modules.end()) continue;
    const auto p =
        render::project(vp, {m.pose.position[0], m.pose.position[1], m.pose.position[2]}, view_.width, view_.height);
    inside += p && p->x >= 0 && p->y >= 0 && p->x < float(view_.width) && p->y < float(view_.height);
  }
  return inside;
}

void Debugger::reveal_group() {
  model_.reveal_group = false;
  std::vector<sim::ModuleId> group;
  for (const render::SceneGroup& g : readout_.scene.groups)
    group.insert(group.end(), g.modules.begin(), g.modules.end());
  if (group.empty() && model_.selected) group.push_back(*model_.selected);
  if (modules_in_view(group) < int(group.size())) place_camera();  // the whole ensemble, the group in it
}

bool Debugger::steer_camera(bool hovered) {
  ImGuiIO& io = ImGui::GetIO();
  const bool active = ImGui::IsItemActive();
  if (active && ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {
    dragging_ = true;
    model_.camera.orbit(io.MouseDelta.x, io.MouseDelta.y);
  } else if (active &&
             (ImGui::IsMouseDragging(ImGuiMouseButton_Right) || ImGui::IsMouseDragging(ImGuiMouseButton_Middle))) {
    dragging_ = true;
    model_.camera.pan(io.MouseDelta.x, io.MouseDelta.y, int(float(view_.height) / io.DisplayFramebufferScale.y));
  }
  if (hovered && io.MouseWheel != 0) model_.camera.zoom(io.MouseWheel);
  bool click = false;
  if (ImGui::IsMouseReleased(ImGuiMouseButton_Left)) {
    click = hovered && !dragging_;
    dragging_ = false;
  }
  if (ImGui::IsMouseReleased(ImGuiMouseButton_Right) || ImGui::IsMouseReleased(ImGuiMouseButton_Middle))
    dragging_ = false;
  return click;
}

}  // namespace dw::view
