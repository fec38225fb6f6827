#include "app/view/debugger.h"

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "app/output_files.h"
#include "app/view/widgets.h"
#include "render/annotations.h"
#include "render/picking.h"

namespace dw::view {
namespace {

// Steps a request asks for when playing as fast as possible adapt so that one takes about this.
constexpr double kFastRequestSeconds = 0.02;

}  // namespace

std::string vec_text(glm::vec3 v) {
  std::ostringstream s;
  s.imbue(std::locale::classic());
  s.precision(6);
  s << v.x << "," << v.y << "," << v.z;
  return s.str();
}

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
  io.Fonts->AddFontFromFileTTF(DWATCH_FONT_FILE, 16.0f);
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window_.handle(), true);
  ImGui_ImplOpenGL3_Init("#version 330 core");
  model_.color_by = scenario_.view.color_by;
  edit_name_ = "w" + std::to_string(session_.model().watches.size() + 1);
  const std::string save_path = app::file_name_part(scenario_.name) + "-branch.toml";
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

void Debugger::send(const std::string& line) {
  // Parsed on the worker too: checking a command reads the session (a push needs bodies), which
  // only the job that holds it may do.
  worker_->submit([this, line](sim::Session&, const sim::Control& control) {
    Answer a{line, {}, {}};
    const auto start = std::chrono::steady_clock::now();
    const watch::SourceText source("<window>", line);
    auto parsed = shell_.parse(source, 0, 1);
    if (auto* ds = std::get_if<std::vector<watch::Diagnostic>>(&parsed)) {
      a.error = watch::format_diagnostics(source, *ds);
    } else if (auto& command = std::get<std::optional<app::SessionCommand>>(parsed)) {
      try {
        auto result = shell_.execute(*command, control);
        if (auto* error = std::get_if<std::string>(&result)) a.error = *error;
        else a.json = std::move(std::get<nlohmann::ordered_json>(result));
      } catch (const std::exception& e) {  // a program failed: the session stays where it got to
        a.error = e.what();
      }
    }
    last_job_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::lock_guard lock(answers_mutex_);
    answers_.push_back(std::move(a));
  });
}

void Debugger::apply(const std::vector<std::string>& commands) {
  for (const std::string& c : commands) send(c);
}

void Debugger::status(std::string message, bool failed) {
  while (!message.empty() && message.back() == '\n') message.pop_back();
  status_ = std::move(message);
  status_failed_ = failed;
}

void Debugger::refresh_frame() {
  // Answers first: a pause stops playing and selects the group it matched.
  std::optional<std::pair<std::string, int64_t>> paused;
  {
    std::lock_guard lock(answers_mutex_);
    for (; answers_seen_ < answers_.size(); ++answers_seen_) {
      const Answer& a = answers_[answers_seen_];
      if (!a.error.empty()) {
        status(a.line + ": " + a.error, true);
        model_.playing = false;
        // A save that would overwrite a file: the panel asks before sending it again.
        if (a.line.rfind("save ", 0) == 0 && a.error.find(" exists; ") != std::string::npos) save_refused_ = save_sent_;
        continue;
      }
      // A pause, or the match a run was asked to stop at: the group is shown the same way.
      const char* stop = a.json.contains("paused") && !a.json["paused"].is_null()     ? "paused"
                         : a.json.contains("matched") && !a.json["matched"].is_null() ? "matched"
                                                                                      : nullptr;
      if (stop) {
        model_.playing = false;
        const auto& p = a.json[stop];
        paused.emplace(p.value("watch", ""), p.value("t", int64_t{0}));
        paused_on_ = stop == std::string_view("paused") ? p.value("watch", "") : "";
        status(answer_words(a.json));
      } else {
        if (a.json.contains("current")) paused_on_.clear();
        if (!model_.playing) status(answer_words(a.json));
      }
    }
  }
  const uint64_t version = worker_->finished();
  if (!paused && version == frame_.version && !frame_stale_) return;
  const bool read = worker_->try_read([&](sim::Session& s) {
    if (paused) {
      const int w = s.watch_index(paused->first);
      if (w >= 0) {
        const auto [first, last] = s.matches(uint32_t(w)).at(paused->second);
        if (first < last) {
          model_.selected_match = MatchRef{uint32_t(w), first};
          const size_t k = size_t(s.model().watches[size_t(w)].watchpoint.program.slot_count());
          model_.selected = s.matches(uint32_t(w)).slots[first * k];
          model_.reveal_group = true;
        }
      }
    }
    FrameRequest request{version, module_window_ ? &*module_window_ : nullptr, timeline_, timeline_columns_};
    // While playing, the matches table is read again twice a second, not at every step.
    const auto now = std::chrono::steady_clock::now();
    // The rows depend only on the filter and the match lists, which a seek leaves as they are.
    std::string rows_key = std::to_string(model_.filter.watch) + "|" +
                           (model_.filter.module ? std::to_string(*model_.filter.module) : "-") + "|" +
                           std::to_string(int(model_.filter.order)) + std::to_string(model_.filter.descending) + "|" +
                           std::to_string(s.interventions().size());
    for (uint32_t w = 0; w < s.model().watches.size(); ++w)
      rows_key += "|" + s.model().watches[w].watchpoint.source->text() + "#" + std::to_string(s.matches(w).size());
    if (rows_key == rows_key_ || (model_.playing && now - rows_read_at_ < std::chrono::milliseconds(500))) {
      request.keep_rows = &frame_;
    } else {
      rows_read_at_ = now;
      rows_key_ = std::move(rows_key);
    }
    Frame next = read_frame(s, scenario_, model_, request);
    frame_ = std::move(next);
  });
  if (!read) return;  // a job runs: the last Frame stays on screen
  // A program failure, new: its module is selected (the run stands at the last step that went through).
  if (frame_.failure && (!shown_failure_ || shown_failure_->step != frame_.failure->step ||
                         shown_failure_->module != frame_.failure->module)) {
    model_.selected = frame_.failure->module;
    model_.playing = false;
  }
  shown_failure_ = frame_.failure;
  frame_stale_ = false;
  drawn_key_.clear();

  // The inspector's history of the selected module, when it is not the current step's.
  if (model_.selected && !model_.playing && !module_window_asked_ && frame_.at.current >= 0 &&
      !(module_window_ && module_window_->module == *model_.selected && module_window_->to == frame_.at.current)) {
    module_window_asked_ = true;
    const sim::ModuleId m = *model_.selected;
    worker_->submit(
        [this, m](sim::Session& s, const sim::Control& control) {
          auto w = read_module_window(s, m, FrameLimits{}.plot_steps, control);
          if (w) module_window_ = std::move(*w);
          module_window_asked_ = false;
        },
        /*background=*/true);
  }
}

void Debugger::handle_keys() {
  const ImGuiIO& io = ImGui::GetIO();
  if (io.WantTextInput) return;
  struct Binding {
    int glfw_key;
    Key key;
  };
  static constexpr Binding kBindings[] = {
      {GLFW_KEY_SPACE, Key::Space}, {GLFW_KEY_RIGHT, Key::Right}, {GLFW_KEY_LEFT, Key::Left},
      {GLFW_KEY_N, Key::N},         {GLFW_KEY_P, Key::P},         {GLFW_KEY_F, Key::F},
      {GLFW_KEY_Z, Key::Z},         {GLFW_KEY_HOME, Key::Home},   {GLFW_KEY_END, Key::End},
      {GLFW_KEY_F1, Key::F1},       {GLFW_KEY_F12, Key::F12},     {GLFW_KEY_ESCAPE, Key::Escape},
  };
  for (const Binding& b : kBindings) {
    if (!ImGui::IsKeyPressed(b.glfw_key, b.key == Key::Right || b.key == Key::Left)) continue;
    if (b.key == Key::Escape) worker_->cancel();
    press(b.key);
  }
}

void Debugger::press(Key key) {
  const size_t w = size_t(model_.chosen_watch);
  const std::span<const int64_t> steps = w < frame_.watches.size()
                                             ? std::span<const int64_t>(frame_.watches[w].nearest_steps)
                                             : std::span<const int64_t>();
  apply(model_.on_key(key, frame_.at, steps, w < frame_.watches.size() ? frame_.watches[w].name : std::string()));
  if (model_.screenshot_requested) {
    model_.screenshot_requested = false;
    const std::string path = "dwatch-" + app::file_name_part(scenario_.name) + "-step-" +
                             std::to_string(std::max<int64_t>(0, frame_.at.current)) + ".png";
    const std::string error = screenshot_view(path);
    status(error.empty() ? "screenshot of the 3D view -> " + path : error, !error.empty());
  }
  if (key == Key::F) drawn_key_.clear();
}

void Debugger::play() {
  if (!model_.playing || suspend_play_ || !worker_->idle() || frame_stale_ || frame_.version != worker_->finished())
    return;
  const auto now = std::chrono::steady_clock::now();
  const double since = std::chrono::duration<double>(now - last_request_).count();
  const int64_t last = frame_.at.end > 0 ? frame_.at.end - 1 : INT64_MAX;
  if (frame_.at.current >= last) {
    model_.playing = false;
    status("the scenario's end (step " + std::to_string(last) + "): step on with -> or `run` past it");
    return;
  }
  int64_t n;
  if (model_.speed <= 0) {
    // As many steps a request as take about kFastRequestSeconds, from what the last playing
    // request took a step (play only asks when the worker is idle, so the last job was it).
    if (fast_asked_ > 0 && last_job_seconds_ > 0) {
      const double per_step = last_job_seconds_ / double(fast_asked_);
      fast_steps_ = std::clamp<int64_t>(int64_t(kFastRequestSeconds / per_step), 1, 1000);
    }
    n = fast_steps_;
  } else {
    n = model_.steps_due(since);
    if (n < 1) return;
  }
  n = std::min(n, last - frame_.at.current);
  fast_asked_ = model_.speed <= 0 ? n : 0;
  send(command::step(n));
  last_request_ = now;
}

render::Scene& Debugger::camera_scene() {
  const render::Camera c = model_.camera.camera();
  frame_.scene.camera_eye = sim::Vec3{c.eye.x, c.eye.y, c.eye.z};
  frame_.scene.camera_target = sim::Vec3{c.target.x, c.target.y, c.target.z};
  return frame_.scene;
}

void Debugger::place_camera() {
  if (view_.width < 16 || view_.height < 16 || frame_.scene.modules.empty()) return;
  window_.make_current();
  model_.camera = OrbitCamera::looking(renderer_->fitted_camera(frame_.scene, view_.width, view_.height));
  model_.camera_placed = true;
}

void Debugger::focus_on_selection() {
  model_.focus_selection = false;
  if (!model_.selected) return;
  for (const render::SceneModule& m : frame_.scene.modules)
    if (m.id == *model_.selected) {
      model_.camera.target = {m.pose.position[0], m.pose.position[1], m.pose.position[2]};
      return;
    }
}

int Debugger::modules_in_view(std::span<const sim::ModuleId> modules) {
  window_.make_current();
  const glm::mat4 vp = renderer_->view_projection(camera_scene(), view_.width, view_.height);
  int inside = 0;
  for (const render::SceneModule& m : frame_.scene.modules) {
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
  for (const render::SceneGroup& g : frame_.scene.groups) group.insert(group.end(), g.modules.begin(), g.modules.end());
  if (group.empty() && model_.selected) group.push_back(*model_.selected);
  if (modules_in_view(group) < int(group.size())) place_camera();  // the whole ensemble, the group in it
}

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
  const std::string key = std::to_string(frame_.version) + "|" + vec_text(model_.camera.eye()) + "|" +
                          vec_text(model_.camera.target) + "|" + std::to_string(width) + "x" + std::to_string(height);
  if (key == drawn_key_) return;
  // While it moves, the renderer's interactive path (no edge smoothing, opaque); still, in full.
  renderer_->draw(camera_scene(), width, height, view_fbo_,
                  moving ? render::RenderQuality::Moving : render::RenderQuality::Full);
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

void Debugger::draw_view() {
  place(panels_.view);
  ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0, 0));
  ImGui::PushStyleVar(ImGuiStyleVar_WindowBorderSize, 0);  // a border would cover the picture's edge
  // No background: the picture is copied into the window's framebuffer before ImGui draws (see
  // frame()), which a software rasteriser does far faster than it samples a textured quad.
  ImGui::Begin("3D view", nullptr,
               ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse | ImGuiWindowFlags_NoBackground);
  ImGui::PopStyleVar(2);

  // The tool row: colour-by, fit, centre, screenshot.
  ImGui::SetCursorPos(ImVec2(ImGui::GetCursorPosX() + 6, ImGui::GetCursorPosY() + 4));
  ImGui::SetNextItemWidth(160);
  const auto& variables = session_.model().universe.variables;  // fixed for the run
  if (ImGui::BeginCombo("colour by", model_.color_by.empty() ? "(one colour)" : model_.color_by.c_str())) {
    if (ImGui::Selectable("(one colour)", model_.color_by.empty())) model_.color_by.clear(), frame_stale_ = true;
    for (const std::string& v : variables)
      if (ImGui::Selectable(v.c_str(), v == model_.color_by)) model_.color_by = v, frame_stale_ = true;
    ImGui::EndCombo();
  }
  ImGui::SameLine();
  if (button("Fit (F)")) press(Key::F);
  ImGui::SameLine();
  if (button("Centre (Z)")) press(Key::Z);
  ImGui::SameLine();
  if (button("Screenshot (F12)")) press(Key::F12);
  // Record: a video of the steps as they show (.mp4 or .webm).
  if (!video_) {
    if (!video_path_[0])
      std::snprintf(video_path_, sizeof video_path_, "dwatch-%s.mp4", app::file_name_part(scenario_.name).c_str());
    flow(160 + ImGui::GetStyle().ItemSpacing.x + button_width("Record"));
    ImGui::SetNextItemWidth(160);
    ImGui::InputText("##video", video_path_, sizeof video_path_);
    note_widget("video-file");
    ImGui::SameLine();
    if (button("Record")) start_recording(video_path_);
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("A video of the 3D view, a frame per step as the steps show (.mp4: H.264, .webm: VP9)");
  } else {
    const int64_t frames = video_->frames();
    flow(button_width("Stop recording"));
    if (button("Stop recording")) stop_recording();
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(1.0f, 0.35f, 0.3f, 1.0f), "REC %" PRId64 " frames", frames);
  }

  const ImVec2 avail = ImGui::GetContentRegionAvail();
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  const ImVec2 scale = ImGui::GetIO().DisplayFramebufferScale;
  view_ = {origin.x * scale.x, origin.y * scale.y, std::max(16, int(avail.x * scale.x)),
           std::max(16, int(avail.y * scale.y))};
  if (!model_.camera_placed) place_camera();
  if (model_.focus_selection) focus_on_selection();
  if (model_.reveal_group && worker_->idle() && !frame_stale_) reveal_group();
  const glm::vec3 eye = model_.camera.eye();
  // Moving: playing, the camera turning, or the step just changed (a click on the timeline or a
  // match shows the step at once, drawn smaller, and in full at the next frame).
  const bool moving =
      model_.playing || eye != last_eye_ || model_.camera.target != last_target_ || frame_.version != last_version_;
  last_eye_ = eye;
  last_target_ = model_.camera.target;
  last_version_ = frame_.version;
  render_view_texture(moving);
  const ImVec2 size(float(view_.width) / scale.x, float(view_.height) / scale.y);
  ImGui::InvisibleButton(
      "view", size,
      ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight | ImGuiButtonFlags_MouseButtonMiddle);
  const ImVec2 mouse = ImGui::GetIO().MousePos;
  view_input((mouse.x - origin.x) * scale.x, (mouse.y - origin.y) * scale.y, ImGui::IsItemHovered());
  ImGui::End();
}

std::optional<sim::ModuleId> Debugger::module_at(float x, float y) {
  const glm::mat4 vp = renderer_->view_projection(camera_scene(), view_.width, view_.height);
  return render::pick(frame_.scene, vp, view_.width, view_.height, {x, y});
}

void Debugger::view_input(float x, float y, bool hovered) {
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
  if (ImGui::IsMouseReleased(ImGuiMouseButton_Left)) {
    if (hovered && !dragging_) {
      model_.on_module_click(module_at(x, y));
      frame_stale_ = true;
    }
    dragging_ = false;
  }
  if (ImGui::IsMouseReleased(ImGuiMouseButton_Right) || ImGui::IsMouseReleased(ImGuiMouseButton_Middle))
    dragging_ = false;

  hovered_.reset();
  if (hovered && !dragging_) hovered_ = module_at(x, y);
  if (hovered_) {
    const sim::Model& m = session_.model();
    ImGui::BeginTooltip();
    ImGui::Text("module %u", m.universe.id(*hovered_));
    if (!frame_.color_values.empty() && *hovered_ < frame_.color_values.size())
      ImGui::Text("%s = %lld", model_.color_by.c_str(), static_cast<long long>(frame_.color_values[*hovered_]));
    ImGui::TextDisabled("click to select");
    ImGui::EndTooltip();
  }
}

std::string Debugger::screenshot_view(const std::string& path) {
  if (std::string clash = app::file_clash(scenario_.inputs, {{"screenshot", path}}); !clash.empty()) return clash;
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

void Debugger::frame() {
  const auto start = std::chrono::steady_clock::now();
  glfwPollEvents();
  refresh_frame();
  window_.make_current();
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  handle_keys();
  play();
  drawing_widgets_.clear();
  drawing_cut_labels_.clear();
  const ImGuiViewport* vp = ImGui::GetMainViewport();
  const int lanes = int(frame_.watches.size()) + 1;
  panels_ = panel_layout(vp->WorkPos.x, vp->WorkPos.y, vp->WorkSize.x, vp->WorkSize.y, lanes);
  // Laid out again when the window's size changes, or the timeline's lanes do (once a Frame was
  // read: before, there are none to count, and the layout file's places stand).
  const bool read = frame_.at.end > 0;
  const bool lanes_changed = read && panels_lanes_ > 0 && lanes != panels_lanes_;
  if (read) panels_lanes_ = lanes;
  const bool resized = vp->WorkSize.x != panels_width_ || vp->WorkSize.y != panels_height_ || lanes_changed;
  panels_cond_ = resized && panels_width_ > 0 ? ImGuiCond_Always : ImGuiCond_FirstUseEver;
  panels_width_ = vp->WorkSize.x;
  panels_height_ = vp->WorkSize.y;
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

bool Debugger::compose(int width, int height) {
  // What ImGui drew this frame, as a hash of its vertices, indices and commands: unchanged, the
  // panels need not be rasterised again (llvmpipe spends most of a frame doing that).
  const ImDrawData* data = ImGui::GetDrawData();
  uint64_t hash = 1469598103934665603ull;
  auto mix = [&](const void* bytes, size_t n) {
    const auto* p = static_cast<const unsigned char*>(bytes);
    for (size_t i = 0; i < n; ++i) hash = (hash ^ p[i]) * 1099511628211ull;
  };
  bool over_view = false;  // some of ImGui's drawing lies on the 3D view (a tooltip, a popup)
  // (Inset by a few pixels: the neighbouring panels' borders run along its edges.)
  const float vx0 = view_.x + 3, vy0 = view_.y + 3, vx1 = view_.x + float(view_.width) - 3,
              vy1 = view_.y + float(view_.height) - 3;
  for (int l = 0; l < data->CmdListsCount; ++l) {
    const ImDrawList* list = data->CmdLists[l];
    mix(list->VtxBuffer.Data, size_t(list->VtxBuffer.Size) * sizeof(ImDrawVert));
    mix(list->IdxBuffer.Data, size_t(list->IdxBuffer.Size) * sizeof(ImDrawIdx));
    for (const ImDrawCmd& c : list->CmdBuffer) {
      mix(&c.ClipRect, sizeof c.ClipRect);
      mix(&c.ElemCount, sizeof c.ElemCount);
    }
    for (const ImDrawVert& v : list->VtxBuffer)
      if (v.pos.x > vx0 && v.pos.x < vx1 && v.pos.y > vy0 && v.pos.y < vy1) over_view = true;
  }
  mix(&width, sizeof width);
  mix(&height, sizeof height);
  const bool ui_changed = hash != composed_ui_hash_ || over_view;
  const bool view_changed = drawn_key_ != composed_view_key_;
  if (!ui_changed && !view_changed) return false;

  const render::Gl& gl = window_.gl();
  if (composed_width_ != width || composed_height_ != height) {
    if (!composed_fbo_) {
      gl.GenFramebuffers(1, &composed_fbo_);
      gl.GenRenderbuffers(1, &composed_color_);
    }
    gl.BindRenderbuffer(GL_RENDERBUFFER, composed_color_);
    gl.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    gl.BindFramebuffer(GL_FRAMEBUFFER, composed_fbo_);
    gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, composed_color_);
    composed_width_ = width;
    composed_height_ = height;
  }
  gl.BindFramebuffer(GL_FRAMEBUFFER, composed_fbo_);
  if (ui_changed) {
    gl.Viewport(0, 0, width, height);
    gl.ClearColor(0.1f, 0.1f, 0.12f, 1);
    gl.Clear(GL_COLOR_BUFFER_BIT);
  }
  if (view_texture_ && drawn_width_ > 0) {
    // The 3D view, stretched when it was drawn smaller while moving; GL's rows run bottom up.
    const int x0 = int(view_.x), y0 = height - int(view_.y) - view_.height;
    gl.BindFramebuffer(GL_READ_FRAMEBUFFER, view_fbo_);
    gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, composed_fbo_);
    gl.BlitFramebuffer(0, 0, drawn_width_, drawn_height_, x0, y0, x0 + view_.width, y0 + view_.height,
                       GL_COLOR_BUFFER_BIT, drawn_width_ == view_.width ? GL_NEAREST : GL_LINEAR);
    gl.BindFramebuffer(GL_FRAMEBUFFER, composed_fbo_);
  }
  // ImGui draws into whatever framebuffer is bound; it touches nothing of the 3D view's area but
  // what lies over it (then `over_view` redrew everything in order).
  if (ui_changed) ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
  composed_ui_hash_ = hash;
  composed_view_key_ = drawn_key_;
  return true;
}

bool Debugger::settled() {
  return worker_->idle() && frame_.version == worker_->finished() && !frame_stale_ && !module_window_asked_;
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
