#include "render/osmesa_context.h"

#include <GL/osmesa.h>

namespace dw::render {

std::variant<std::unique_ptr<OsMesaContext>, std::string> OsMesaContext::create() {
  const int attributes[] = {OSMESA_FORMAT,
                            OSMESA_RGBA,
                            OSMESA_DEPTH_BITS,
                            0,  // depth lives in the renderer's framebuffers
                            OSMESA_PROFILE,
                            OSMESA_CORE_PROFILE,
                            OSMESA_CONTEXT_MAJOR_VERSION,
                            3,
                            OSMESA_CONTEXT_MINOR_VERSION,
                            3,
                            0};
  std::unique_ptr<OsMesaContext> c(new OsMesaContext());
  c->context_ = OSMesaCreateContextAttribs(attributes, nullptr);
  if (!c->context_) return std::string("OSMesa could not create an OpenGL 3.3 core context");
  c->make_current();
  std::string missing = load_gl(c->gl_, &OSMesaGetProcAddress);
  if (!missing.empty()) return "the OSMesa context lacks " + missing;
  return c;
}

OsMesaContext::~OsMesaContext() {
  if (!context_) return;
  if (OSMesaGetCurrentContext() == static_cast<OSMesaContext>(context_)) OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
  OSMesaDestroyContext(static_cast<OSMesaContext>(context_));
}

void OsMesaContext::make_current() {
  OSMesaMakeCurrent(static_cast<OSMesaContext>(context_), pixel_, GL_UNSIGNED_BYTE, 1, 1);
}

}  // namespace dw::render
