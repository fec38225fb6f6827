// The debugger's window: a GLFW 3.3 window with a GL 3.3 core context, the renderer's functions
// loaded through glfwGetProcAddress (render/gl.h says why through a table). The 3D view and
// Dear ImGui draw into the same context.
#pragma once

#include <memory>
#include <string>
#include <variant>

#include "render/gl_context.h"

struct GLFWwindow;

namespace dw::view {

class GlfwWindow final : public render::GlContext {
 public:
  // The window, or why there is none (no display, no GL 3.3).
  static std::variant<std::unique_ptr<GlfwWindow>, std::string> create(int width, int height, const std::string& title);
  ~GlfwWindow() override;
  GlfwWindow(const GlfwWindow&) = delete;
  GlfwWindow& operator=(const GlfwWindow&) = delete;

  void make_current() override;
  const render::Gl& gl() const override { return gl_; }
  GLFWwindow* handle() const { return window_; }

 private:
  GlfwWindow() = default;
  GLFWwindow* window_ = nullptr;
  render::Gl gl_;
};

}  // namespace dw::view
