// Where the panels go: the tiling of the window (panel_layout, view_model.h) applied to each
// panel, the first time from the layout file if there is one (ImGui keeps the places a person
// gave the panels there), and again whenever the window's size or the timeline's lanes change, the
// Why panel opens or closes, or the Statistics panel's tab changes between its plots and its rows.
#include <imgui.h>

#include <cstdlib>
#include <filesystem>

#include "app/view/debugger.h"

namespace dw::view {

std::string layout_file() {
  std::filesystem::path dir;
  if (const char* xdg = std::getenv("XDG_CONFIG_HOME"); xdg && *xdg) dir = xdg;
  else if (const char* home = std::getenv("HOME"); home && *home) dir = std::filesystem::path(home) / ".config";
  else return {};
  std::error_code ec;
  std::filesystem::create_directories(dir / "dwatch", ec);
  if (ec) return {};
  return (dir / "dwatch" / "view.ini").string();
}

void Debugger::lay_out_panels() {
  const ImGuiViewport* vp = ImGui::GetMainViewport();
  const int lanes = int(readout_.watches.size()) + 1;
  panels_ = panel_layout(vp->WorkPos.x, vp->WorkPos.y, vp->WorkSize.x, vp->WorkSize.y, lanes, why_open_, tall_tabs_);
  // Laid out again when the window's size changes, or the timeline's lanes do (once a Readout was
  // read: before, there are none to count, and the layout file's places stand).
  const bool read = readout_.at.end > 0;
  const bool lanes_changed = read && panels_lanes_ > 0 && lanes != panels_lanes_;
  if (read) panels_lanes_ = lanes;
  // The Why panel opening or closing gives the 3D view's place to it, or back.
  const bool why_changed = why_open_ != panels_why_;
  panels_why_ = why_open_;
  // A tab of the Statistics panel that lists rows (group, marks, diff) takes more of the column.
  const bool tabs_changed = tall_tabs_ != panels_tall_tabs_;
  panels_tall_tabs_ = tall_tabs_;
  const bool resized = vp->WorkSize.x != panels_width_ || vp->WorkSize.y != panels_height_ || lanes_changed ||
                       why_changed || tabs_changed;
  panels_cond_ = resized && panels_width_ > 0 ? ImGuiCond_Always : ImGuiCond_FirstUseEver;
  panels_width_ = vp->WorkSize.x;
  panels_height_ = vp->WorkSize.y;
}

void Debugger::place(const PanelRect& r) const {
  ImGui::SetNextWindowPos(ImVec2(r.x, r.y), panels_cond_);
  ImGui::SetNextWindowSize(ImVec2(r.width, r.height), panels_cond_);
}

}  // namespace dw::view
