#include "render/gl.h"

namespace dw::render {

std::string load_gl(Gl& gl, GetProcAddress get_proc_address) {
  std::string missing;
#define DW_GL_LOAD(type, name)                                    \
  gl.name = reinterpret_cast<type>(get_proc_address("gl" #name)); \
  if (!gl.name) missing += (missing.empty() ? "" : ", ") + std::string("gl" #name);
  DW_GL_FUNCTIONS(DW_GL_LOAD)
#undef DW_GL_LOAD
  return missing;
}

}  // namespace dw::render
