#include "app/view/glfw_window.h"

#include <GLFW/glfw3.h>

namespace dw::view {
namespace {

std::string glfw_error() {
  const char* description = nullptr;
  glfwGetError(&description);
  return description ? description : "unknown GLFW error";
}

}  // namespace

std::variant<std::unique_ptr<GlfwWindow>, std::string> GlfwWindow::create(int width, int height,
                                                                          const std::string& title) {
  if (!glfwInit()) return "cannot open a window: " + glfw_error() + " (is DISPLAY set? headless: xvfb-run)";
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  std::unique_ptr<GlfwWindow> w(new GlfwWindow());
  w->window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!w->window_) {
    std::string why = glfw_error();
    glfwTerminate();
    return "cannot open an OpenGL 3.3 core window: " + why;
  }
  w->make_current();
  glfwSwapInterval(0);  // the frame loop paces itself; a benchmark measures frames, not vsync
  if (std::string missing = render::load_gl(w->gl_, &glfwGetProcAddress); !missing.empty())
    return "the window's OpenGL context lacks " + missing;
  return w;
}

GlfwWindow::~GlfwWindow() {
  if (window_) glfwDestroyWindow(window_);
  glfwTerminate();
}

void GlfwWindow::make_current() { glfwMakeContextCurrent(window_); }

}  // namespace dw::view
