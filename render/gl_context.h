// Where the renderer draws (docs/design.md §9): a GL 3.3 core context and the functions loaded from it.
// An OSMesa context draws headless (render/osmesa_context.h); the debugger's GLFW window is
// another implementation. The renderer sees only this interface.
#pragma once

#include "render/gl.h"

namespace dw::render {

class GlContext {
 public:
  virtual ~GlContext() = default;
  // Makes this context the calling thread's current one.
  virtual void make_current() = 0;
  // The functions, loaded through the context's own proc-address function.
  virtual const Gl& gl() const = 0;
};

}  // namespace dw::render
