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

Image read_framebuffer(const Gl& gl, unsigned framebuffer, int width, int height) {
  gl.BindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
  Image image(width, height);
  gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
  gl.ReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
  gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
  // GL's rows run bottom to top; images run top to bottom.
  const size_t row = size_t(width) * 4;
  std::vector<uint8_t> swap(row);
  for (int y = 0; y < height / 2; ++y) {
    uint8_t* a = image.rgba.data() + size_t(y) * row;
    uint8_t* b = image.rgba.data() + size_t(height - 1 - y) * row;
    std::copy(a, a + row, swap.data());
    std::copy(b, b + row, a);
    std::copy(swap.data(), swap.data() + row, b);
  }
  for (size_t i = 3; i < image.rgba.size(); i += 4) image.rgba[i] = 255;
  return image;
}

}  // namespace dw::render
