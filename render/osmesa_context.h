// A headless GL 3.3 core context: Mesa's OSMesa (llvmpipe, in software), made with
// OSMesaCreateContextAttribs. The renderer draws into its own framebuffer objects, so the
// context's own buffer is a single pixel. OSMesa is opened when a context is made, not linked
// (osmesa_context.cpp says why).
#pragma once

#include <memory>
#include <string>
#include <variant>

#include "render/gl_context.h"

namespace dw::render {

class OsMesaContext final : public GlContext {
 public:
  // The context, or why there is none.
  static std::variant<std::unique_ptr<OsMesaContext>, std::string> create();
  ~OsMesaContext() override;
  OsMesaContext(const OsMesaContext&) = delete;
  OsMesaContext& operator=(const OsMesaContext&) = delete;

  void make_current() override;
  const Gl& gl() const override { return gl_; }

 private:
  struct Library;
  OsMesaContext();
  std::unique_ptr<Library> library_;
  void* context_ = nullptr;  // OSMesaContext, kept opaque so <GL/osmesa.h> stays in the .cpp
  unsigned char pixel_[4] = {};
  Gl gl_;
};

}  // namespace dw::render
