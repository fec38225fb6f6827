// The 3D view's panel: its tool row (colour by, fit, centre, screenshot, record), the picture the
// renderer draws into a texture (smaller while it moves, in full once it holds still), the mouse
// over it (camera.cpp, picking.cpp) and its screenshot.
#include <imgui.h>

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>

#include "app/view/debugger.h"
#include "app/view/widgets.h"
#include "shell/output_files.h"

namespace dw::view {

void Debugger::render_view_texture(bool moving) {
  const render::Gl& gl = window_.gl();
  if (!view_fbo_) {
    gl.GenFramebuffers(1, &view_fbo_);
    gl.GenTextures(1, &view_texture_);
  }
  if (texture_width_ != view_.width || texture_height_ != view_.height) {
    gl.BindTexture(GL_TEXTURE_2D, view_texture_);
    gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, view_.width, view_.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl.BindFramebuffer(GL_FRAMEBUFFER, view_fbo_);
    gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, view_texture_, 0);
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    texture_width_ = view_.width;
    texture_height_ = view_.height;
    drawn_key_.clear();
  }
  const float scale = moving ? kMotionScale : 1.0f;
  const int width = std::max(16, int(float(view_.width) * scale)),
            height = std::max(16, int(float(view_.height) * scale));
  const std::string key = std::to_string(readout_.version) + "|" + vec_text(model_.camera.eye()) + "|" +
                          vec_text(model_.camera.target) + "|" + std::to_string(width) + "x" + std::to_string(height);
  if (key == drawn_key_) return;
  // While it moves, the renderer's interactive path (no edge smoothing, opaque); still, in full.
  // Its title and labels at least as large as the panels' text (a small window's 3D view wrote
  // them ~9 pixels high), scaled with the picture while it moves; picking and screenshots use the
  // full size's.
  const int least_text = int(ImGui::GetFontSize() * ImGui::GetIO().DisplayFramebufferScale.y);
  renderer_->set_least_text_size(std::max(1, int(float(least_text) * scale)));
  renderer_->draw(camera_scene(), width, height, view_fbo_,
                  moving ? render::RenderQuality::Moving : render::RenderQuality::Full);
  renderer_->set_least_text_size(least_text);
  // Blending leaves alpha below 1 where translucent things were drawn, and ImGui blends the image
  // over the window: the picture is opaque, as `dwatch render` writes it.
  gl.BindFramebuffer(GL_FRAMEBUFFER, view_fbo_);
  gl.ColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_TRUE);
  gl.ClearColor(0, 0, 0, 1);
  gl.Clear(GL_COLOR_BUFFER_BIT);
  gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
  drawn_key_ = key;
  drawn_width_ = width;
  drawn_height_ = height;
}

// A plane across one axis that leaves out the modules beyond it, to see inside a large ensemble:
// the axis (off, x, y, z), and where it stands, from the middle of the ensemble's extent.
void Debugger::cut_tools() {
  static const char* const kAxes[] = {"no cut", "cut x", "cut y", "cut z"};
  int chosen = model_.cut_axis + 1;
  flow(combo_width_of(kAxes));
  choice("cut", chosen, kAxes);
  if (chosen - 1 != model_.cut_axis) {
    model_.cut_axis = chosen - 1;
    if (model_.cut_axis >= 0 && !readout_.scene.modules.empty()) {
      float lo = INFINITY, hi = -INFINITY;
      for (const render::SceneModule& m : readout_.scene.modules) {
        lo = std::min(lo, m.pose.position[size_t(model_.cut_axis)]);
        hi = std::max(hi, m.pose.position[size_t(model_.cut_axis)]);
      }
      model_.cut_at = (lo + hi) / 2;
    }
    readout_stale_ = true;
  }
  if (model_.cut_axis < 0) return;
  ImGui::SameLine();
  ImGui::SetNextItemWidth(90);
  if (ImGui::InputFloat("##cut at", &model_.cut_at, 0.5f, 2.0f, "%.1f")) readout_stale_ = true;
  note_widget("cut-at");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("The modules whose centre lies beyond this are left out");
}

void Debugger::draw_view() {
  place(panels_.view);
  ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0, 0));
  ImGui::PushStyleVar(ImGuiStyleVar_WindowBorderSize, 0);  // a border would cover the picture's edge
  // No background: the picture is copied into the window's framebuffer before ImGui draws (see
  // frame()), which a software rasteriser does far faster than it samples a textured quad.
  ImGui::Begin("3D view", nullptr,
               ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse | ImGuiWindowFlags_NoBackground);
  ImGui::PopStyleVar(2);

  // The tool row: colour-by, fit, zoom to the selection, screenshot, record.
  ImGui::SetCursorPos(ImVec2(ImGui::GetCursorPosX() + 6, ImGui::GetCursorPosY() + 4));
  ImGui::AlignTextToFramePadding();
  ImGui::TextUnformatted("colour by");  // the label before its menu, as it reads
  ImGui::SameLine();
  ImGui::SetNextItemWidth(160);
  const auto& variables = session_.model().universe.variables;  // fixed for the run
  const char* shown = model_.color_by.empty() ? "(one colour)" : model_.color_by.c_str();
  const bool open = ImGui::BeginCombo("##colour_by", shown);
  note_widget("colour by", combo_width(shown));  // a script's `press colour by`, then `press colour by: V`
  if (open) {
    if (ImGui::Selectable("(one colour)", model_.color_by.empty())) model_.color_by.clear(), readout_stale_ = true;
    note_widget("colour by: (one colour)", 0, true);
    for (const std::string& v : variables) {
      if (ImGui::Selectable(v.c_str(), v == model_.color_by)) model_.color_by = v, readout_stale_ = true;
      note_widget("colour by: " + v, 0, true);
    }
    ImGui::EndCombo();
  }
  ImGui::SameLine();
  if (button("Fit (F)")) press(Key::F);
  ImGui::SameLine();
  if (button("Zoom to selection (Z)")) press(Key::Z);
  const std::string isolate = model_.isolate ? "Show all (I)" : "Isolate (I)";
  flow(button_width(isolate));
  if (button(isolate)) press(Key::I);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Only the groups and the selected module: the rest left out");
  cut_tools();
  if (readout_.physics) {
    const std::string contacts = model_.contacts ? "No contacts (C)" : "Contacts (C)";
    flow(button_width(contacts));
    if (button(contacts)) press(Key::C);
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("The contact points the solver worked on in this step, each normal as long as its impulse");
  }
  const std::string follow = model_.followed ? "Stop following (T)" : "Follow (T)";
  flow(button_width(follow));
  if (button(follow)) press(Key::T);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("The camera keeps the selected module at the view's centre as it moves; turn and zoom as ever");
  flow(button_width("Screenshot (F12)"));  // on a line of its own in a narrow window
  if (button("Screenshot (F12)")) press(Key::F12);
  // Record: a video of the steps as they show (.mp4 or .webm).
  if (!video_) {
    if (!video_path_[0])
      std::snprintf(video_path_, sizeof video_path_, "dwatch-%s.mp4", shell::file_name_part(scenario_.name).c_str());
    // The file's name whole (it was cut at 160 pixels), up to 320; on a line of its own in a
    // narrow window, in from the edge as the tool row is (it stood against the window's edge).
    const float text = ImGui::CalcTextSize(video_path_).x + 2 * ImGui::GetStyle().FramePadding.x;
    const float field = std::clamp(text + 4, 160.0f, 320.0f);
    flow(field + ImGui::GetStyle().ItemSpacing.x + button_width("Record"));
    if (ImGui::GetCursorPosX() < 6) ImGui::SetCursorPosX(6);
    ImGui::SetNextItemWidth(field);
    ImGui::InputText("##video", video_path_, sizeof video_path_);
    note_widget("video-file", text);
    ImGui::SameLine();
    if (button("Record")) start_recording(video_path_);
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("A video of the 3D view, a frame per step as the steps show (.mp4: H.264, .webm: VP9)");
  } else {
    const int64_t frames = video_->frames();
    flow(button_width("Stop recording"));
    if (button("Stop recording")) stop_recording();
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(1.0f, 0.35f, 0.3f, 1.0f), "REC %" PRId64 " frame%s", frames, frames == 1 ? "" : "s");
  }

  const ImVec2 avail = ImGui::GetContentRegionAvail();
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  const ImVec2 scale = ImGui::GetIO().DisplayFramebufferScale;
  view_ = {origin.x * scale.x, origin.y * scale.y, std::max(16, int(avail.x * scale.x)),
           std::max(16, int(avail.y * scale.y))};
  if (!model_.camera_placed) place_camera();
  if (model_.focus_selection) focus_on_selection();
  if (model_.reveal_group && worker_->idle() && !readout_stale_) reveal_group();
  follow_module();
  const glm::vec3 eye = model_.camera.eye();
  // Moving: playing, the camera turning, or the step just changed (a click on the timeline or a
  // match shows the step at once, drawn smaller, and in full at the next frame).
  const bool moving =
      model_.playing || eye != last_eye_ || model_.camera.target != last_target_ || readout_.version != last_version_;
  last_eye_ = eye;
  last_target_ = model_.camera.target;
  last_version_ = readout_.version;
  render_view_texture(moving);
  const ImVec2 size(float(view_.width) / scale.x, float(view_.height) / scale.y);
  ImGui::InvisibleButton(
      "view", size,
      ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight | ImGuiButtonFlags_MouseButtonMiddle);
  const ImVec2 mouse = ImGui::GetIO().MousePos;
  view_input((mouse.x - origin.x) * scale.x, (mouse.y - origin.y) * scale.y, ImGui::IsItemHovered());
  why_in_view(origin, scale);
  diff_in_view(origin, scale);
  draw_edge_pointers(origin, scale);
  ImGui::End();
}

std::string Debugger::screenshot_view(const std::string& path) {
  if (std::string clash = shell::file_clash(scenario_.inputs, {{"screenshot", path}}); !clash.empty()) return clash;
  window_.make_current();
  try {
    const render::Image image = renderer_->render(camera_scene(), view_.width, view_.height);
    std::string error;
    if (!render::write_png(path, image, &error)) return error;
  } catch (const render::RenderError& e) {
    return e.what();
  }
  drawn_key_.clear();
  return {};
}

}  // namespace dw::view
