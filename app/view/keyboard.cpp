// The window's keys: GLFW's keys as the view model's (view_model.h says what each sends), and what
// a key does in the window besides (a screenshot of the 3D view, a redraw after a fit).
#include "app/view/debugger.h"  // first: render/gl.h before GLFW's GL header

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>

#include "shell/output_files.h"

namespace dw::view {

void Debugger::handle_keys() {
  const ImGuiIO& io = ImGui::GetIO();
  if (io.WantTextInput) return;
  struct Binding {
    int glfw_key;
    Key key;
  };
  static constexpr Binding kBindings[] = {
      {GLFW_KEY_SPACE, Key::Space},   {GLFW_KEY_RIGHT, Key::Right}, {GLFW_KEY_LEFT, Key::Left},
      {GLFW_KEY_N, Key::N},           {GLFW_KEY_P, Key::P},         {GLFW_KEY_F, Key::F},
      {GLFW_KEY_Z, Key::Z},           {GLFW_KEY_Y, Key::Y},         {GLFW_KEY_I, Key::I},
      {GLFW_KEY_C, Key::C},           {GLFW_KEY_T, Key::T},         {GLFW_KEY_HOME, Key::Home},
      {GLFW_KEY_END, Key::End},       {GLFW_KEY_F1, Key::F1},       {GLFW_KEY_F12, Key::F12},
      {GLFW_KEY_ESCAPE, Key::Escape},
  };
  for (const Binding& b : kBindings) {
    if (!ImGui::IsKeyPressed(b.glfw_key, b.key == Key::Right || b.key == Key::Left)) continue;
    if (b.key == Key::Escape) worker_->cancel();
    press(b.key);
  }
}

void Debugger::press(Key key) {
  const size_t w = size_t(model_.chosen_watch);
  const std::span<const int64_t> steps = w < readout_.watches.size()
                                             ? std::span<const int64_t>(readout_.watches[w].nearest_steps)
                                             : std::span<const int64_t>();
  apply(model_.on_key(key, readout_.at, steps,
                      w < readout_.watches.size() ? readout_.watches[w].spec.name : std::string()));
  if (model_.screenshot_requested) {
    model_.screenshot_requested = false;
    const std::string path = "dwatch-" + shell::file_name_part(scenario_.name) + "-step-" +
                             std::to_string(std::max<int64_t>(0, readout_.at.current)) + ".png";
    const std::string error = screenshot_view(path);
    status(error.empty() ? "screenshot of the 3D view -> " + path : error, !error.empty());
  }
  if (key == Key::F) drawn_key_.clear();
  // The scene leaves the others out or brings them back; its contacts are read or dropped.
  if (key == Key::I || key == Key::C) readout_stale_ = true;
  if (key == Key::Y) why_last_changed();
}

}  // namespace dw::view
