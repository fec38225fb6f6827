// The window's picture, kept between frames: the panels rasterised again only when what ImGui drew
// changed, the 3D view copied in only when it was drawn again (a software rasteriser spends most
// of a frame on the panels).
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include "app/view/debugger.h"

namespace dw::view {

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

}  // namespace dw::view
