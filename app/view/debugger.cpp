// The window's lifecycle: opening it (Dear ImGui's context with its GLFW and OpenGL 3 backends,
// the renderer), the frame loop (input, a fresh Readout, the 3D view and the panels, the picture
// put together and shown), and closing it. What a frame draws lives beside it, one job a file:
// the session link (session_link.cpp), keys (keyboard.cpp), the camera (camera.cpp), picking
// (picking.cpp), the panels' layout (layout.cpp), the 3D view (scene_view.cpp), the window's
// picture (compose.cpp) and the panels themselves (panels.cpp, module_panels.cpp).
#include "app/view/debugger.h"

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <filesystem>

#include "shell/output_files.h"

namespace dw::view {

Debugger::Debugger(const scenarios::Scenario& scenario, sim::Session& session, GlfwWindow& window, std::string layout)
    : scenario_(scenario),
      session_(session),
      window_(window),
      layout_(std::move(layout)),
      shell_(scenario, session),
      worker_(std::make_unique<SessionWorker>(session)) {
  window_.make_current();
  renderer_ = std::make_unique<render::Renderer>(window_.gl());
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = layout_.empty() ? nullptr : layout_.c_str();
  io.Fonts->AddFontFromFileTTF(DWATCH_FONT_FILE, 16.0f);  // the first font added is the default
  if (const auto mono = std::filesystem::path(DWATCH_FONT_FILE).replace_filename("DejaVuSansMono.ttf");
      std::filesystem::exists(mono))
    mono_font_ = io.Fonts->AddFontFromFileTTF(mono.c_str(), 15.0f);
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window_.handle(), true);
  ImGui_ImplOpenGL3_Init("#version 330 core");
  model_.color_by = scenario_.view.color_by;
  edit_name_ = "w" + std::to_string(session_.watches().size() + 1);
  const std::string save_path = shell::file_name_part(scenario_.name) + "-branch.toml";
  save_path.copy(save_path_, sizeof save_path_ - 1);
  last_request_ = std::chrono::steady_clock::now();
}

Debugger::~Debugger() {
  stop_recording();  // a window closed while recording keeps its video
  worker_.reset();   // cancels and joins before anything it uses goes
  window_.make_current();
  const render::Gl& gl = window_.gl();
  if (view_fbo_) gl.DeleteFramebuffers(1, &view_fbo_);
  if (composed_fbo_) gl.DeleteFramebuffers(1, &composed_fbo_);
  if (composed_color_) gl.DeleteRenderbuffers(1, &composed_color_);
  if (view_texture_) gl.DeleteTextures(1, &view_texture_);
  renderer_.reset();
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
}

void Debugger::frame() {
  const auto start = std::chrono::steady_clock::now();
  glfwPollEvents();
  refresh_readout();
  window_.make_current();
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  handle_keys();
  play();
  drawing_widgets_.clear();
  drawing_cut_labels_.clear();
  lay_out_panels();
  draw_view();
  record_frame();
  draw_panels();
  if (model_.show_help) help_window();
  widgets_.swap(drawing_widgets_);
  cut_labels_.swap(drawing_cut_labels_);
  ImGui::Render();

  int width = 0, height = 0;
  glfwGetFramebufferSize(window_.handle(), &width, &height);
  if (compose(width, height)) {
    // Something changed: the finished picture goes to the window.
    const render::Gl& gl = window_.gl();
    gl.BindFramebuffer(GL_READ_FRAMEBUFFER, composed_fbo_);
    gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    gl.BlitFramebuffer(0, 0, width, height, 0, 0, width, height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    glfwSwapBuffers(window_.handle());
  }
  if (!window_shot_.empty()) {
    const render::Image image = render::read_framebuffer(window_.gl(), composed_fbo_, width, height);
    window_shot_error_.clear();
    render::write_png(window_shot_, image, &window_shot_error_);
    window_shot_.clear();
  }
  frame_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (start - frame_time_shown_at_ > std::chrono::milliseconds(500)) {
    shown_frame_ms_ = frame_seconds_ * 1000;
    frame_time_shown_at_ = start;
  }
}

bool Debugger::settled() {
  return worker_->idle() && readout_.version == worker_->finished() && !readout_stale_ && !module_window_asked_ &&
         !group_window_asked_ && !group_series_asked_;
}

void Debugger::settle() {
  suspend_play_ = true;
  while (!settled()) frame();
  suspend_play_ = false;
}

int Debugger::run_interactive() {
  while (!glfwWindowShouldClose(window_.handle())) frame();
  return 0;
}

}  // namespace dw::view
