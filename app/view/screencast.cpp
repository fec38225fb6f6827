// A window script's screencast (`screencast FILE` ... `screencast stop`): a video of the whole
// window, panels and all, as the script drives it — what a walkthrough or a bug report shows. A
// frame per script line, holding the window as the line left it, and `wait N` holds it N frames:
// at 10 frames a second, `wait 10` is a second. Frames follow the script, not the clock, so the
// same script films the same video however long its jobs take (a frame per drawn frame filmed
// the waiting for a job as seconds of one still picture).
#include "app/view/debugger.h"  // first: render/gl.h before GLFW's GL header

#include <GLFW/glfw3.h>

#include <algorithm>

#include "shell/output_files.h"

namespace dw::view {

void Debugger::screencast_command(const std::vector<std::string>& words, nlohmann::ordered_json& answer,
                                  std::string& error) {
  if (words.size() == 2 && words[1] == "stop") {
    if (!screencast_) {
      error = "no screencast is being filmed ('screencast FILE' starts one)";
      return;
    }
    answer["frames"] = screencast_->frames();
    answer["screencast"] = screencast_->path();
    error = finish_screencast();
    return;
  }
  if (screencast_) {
    error = "a screencast is being filmed to " + screencast_->path() + " ('screencast stop' ends it)";
    return;
  }
  if (std::string clash = shell::file_clash(scenario_.inputs, {{"the screencast", words[1]}}); !clash.empty()) {
    error = clash;
    return;
  }
  int width = 0, height = 0;
  glfwGetFramebufferSize(window_.handle(), &width, &height);
  const render::VideoSettings settings{width & ~1, height & ~1, 10};  // yuv420p: even sizes
  auto opened = render::VideoWriter::open(words[1], settings);
  if (auto* message = std::get_if<std::string>(&opened)) {
    error = *message;
    return;
  }
  screencast_ = std::move(std::get<std::unique_ptr<render::VideoWriter>>(opened));
  screencast_settings_ = settings;
  answer["screencast"] = words[1];
  answer["width"] = settings.width;
  answer["height"] = settings.height;
}

std::string Debugger::film_window(int64_t frames) {
  if (!screencast_ || frames <= 0) return {};
  int width = 0, height = 0;
  glfwGetFramebufferSize(window_.handle(), &width, &height);
  window_.make_current();
  const render::Image window = render::read_framebuffer(window_.gl(), composed_fbo_, width, height);
  // The video's size is the window's when filming began; a window resized since is cut or padded.
  render::Image frame(screencast_settings_.width, screencast_settings_.height);
  for (int y = 0; y < frame.height && y < window.height; ++y)
    for (int x = 0; x < frame.width && x < window.width; ++x) std::copy_n(window.pixel(x, y), 4, frame.pixel(x, y));
  for (int64_t i = 0; i < frames; ++i)
    if (std::string error = screencast_->add_frame(frame); !error.empty()) {
      screencast_.reset();  // nothing is left at the path
      return "the screencast stopped: " + error;
    }
  return {};
}

std::string Debugger::finish_screencast() {
  if (!screencast_) return {};
  std::string error = screencast_->finish();
  screencast_.reset();
  return error;
}

}  // namespace dw::view
