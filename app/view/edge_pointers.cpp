// Pointers at the 3D view's edge towards modules out of it (issue 64, defect 12: push_wall tore a
// module off and out of the view, and nothing said where it went), and the camera following a
// module (`T`, the script's `follow M`).
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "app/view/debugger.h"
#include "render/annotations.h"

namespace dw::view {
namespace {

// Every module out of the view gets a pointer while they are this few (a module or two torn off);
// beyond, only the selection, the followed module and the groups' (zoomed in, most of a large
// ensemble is out of the view, and a pointer for each would say nothing).
constexpr int kStrays = 16;
constexpr float kInset = 14;  // the pointer's tip from the view's edge, in window pixels
constexpr float kApart = 22;  // pointers nearer than this are one, "+N" more

ImU32 pointer_color(int rank) {
  switch (rank) {
    case 0: return IM_COL32(40, 200, 80, 255);   // the selection: its ring's green
    case 1: return IM_COL32(90, 170, 255, 255);  // followed
    case 2: return IM_COL32(230, 60, 50, 255);   // a group's: its rim's red
    default: return IM_COL32(245, 245, 245, 255);
  }
}

}  // namespace

void Debugger::follow_module() {
  if (!model_.followed) return;
  for (const render::SceneModule& m : readout_.scene.modules)
    if (m.id == *model_.followed) {
      model_.camera.target = glm::vec3(m.pose.position[0], m.pose.position[1], m.pose.position[2]);
      return;
    }
}

void Debugger::find_edge_pointers(ImVec2 scale) {
  const std::string key = std::to_string(readout_.version) + "|" + vec_text(model_.camera.eye()) + "|" +
                          vec_text(model_.camera.target) + "|" + std::to_string(view_.width) + "x" +
                          std::to_string(view_.height) + "|" +
                          std::to_string(model_.followed ? int64_t(*model_.followed) : -1);
  if (key == pointers_key_) return;
  pointers_key_ = key;
  pointers_.clear();
  const glm::mat4 vp = renderer_->view_projection(camera_scene(), view_.width, view_.height);
  struct Out {
    int rank;
    sim::ModuleId module;
    render::EdgePointer at;
  };
  std::vector<Out> out;
  int strays = 0;
  for (const render::SceneModule& m : readout_.scene.modules) {
    const auto p = render::edge_pointer(vp, {m.pose.position[0], m.pose.position[1], m.pose.position[2]}, view_.width,
                                        view_.height, kInset * scale.x);
    if (!p) continue;
    const int rank = m.selected ? 0 : model_.followed == m.id ? 1 : m.highlighted ? 2 : 3;
    strays += rank == 3;
    out.push_back({rank, m.id, *p});
  }
  if (strays > kStrays) std::erase_if(out, [](const Out& o) { return o.rank == 3; });
  std::stable_sort(out.begin(), out.end(), [](const Out& a, const Out& b) { return a.rank < b.rank; });
  const watch::Universe& universe = session_.model().universe;
  for (const Out& o : out) {
    const glm::vec2 at(o.at.at.x / scale.x, o.at.at.y / scale.y);
    auto near = std::find_if(pointers_.begin(), pointers_.end(),
                             [&](const EdgePointerMark& p) { return glm::length(p.at - at) < kApart; });
    if (near != pointers_.end()) {
      ++near->more;
      continue;
    }
    pointers_.push_back({at, o.at.toward, pointer_color(o.rank), int64_t(universe.id(o.module)), 0});
  }
}

void Debugger::draw_edge_pointers(ImVec2 origin, ImVec2 scale) {
  find_edge_pointers(scale);
  ImDrawList* draw = ImGui::GetWindowDrawList();
  for (const EdgePointerMark& p : pointers_) {
    const ImVec2 tip(origin.x + p.at.x, origin.y + p.at.y);
    const glm::vec2 side(-p.toward.y, p.toward.x);
    const float length = 16, half = 8;
    const ImVec2 a(tip.x - p.toward.x * length + side.x * half, tip.y - p.toward.y * length + side.y * half);
    const ImVec2 b(tip.x - p.toward.x * length - side.x * half, tip.y - p.toward.y * length - side.y * half);
    draw->AddTriangleFilled(tip, a, b, p.color);
    draw->AddTriangle(tip, a, b, IM_COL32(0, 0, 0, 255), 1.5f);
    // Its id (and how many more it stands for) inward from the tip, on a dark plate.
    const std::string text = std::to_string(p.module) + (p.more > 0 ? " +" + std::to_string(p.more) : "");
    const ImVec2 size = ImGui::CalcTextSize(text.c_str());
    const float reach = length + 4 + 0.5f * std::max(size.x * std::abs(p.toward.x), size.y * std::abs(p.toward.y));
    const ImVec2 centre(tip.x - p.toward.x * reach, tip.y - p.toward.y * reach);
    const ImVec2 lo(centre.x - size.x / 2 - 3, centre.y - size.y / 2 - 1);
    const ImVec2 hi(centre.x + size.x / 2 + 3, centre.y + size.y / 2 + 1);
    draw->AddRectFilled(lo, hi, IM_COL32(20, 20, 24, 220), 3);
    draw->AddText(ImVec2(lo.x + 3, lo.y + 1), p.color, text.c_str());
  }
}

}  // namespace dw::view
