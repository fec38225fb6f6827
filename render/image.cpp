#include "render/image.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cstdlib>

namespace dw::render {

bool write_png(const std::string& path, const Image& image, std::string* error) {
  if (stbi_write_png(path.c_str(), image.width, image.height, 4, image.rgba.data(), image.width * 4)) return true;
  if (error) *error = "cannot write " + path;
  return false;
}

std::optional<Image> read_png(const std::string& path, std::string* error) {
  int w = 0, h = 0, channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &w, &h, &channels, 4);
  if (!data) {
    if (error) *error = "cannot read " + path + ": " + stbi_failure_reason();
    return std::nullopt;
  }
  Image image(w, h);
  std::copy(data, data + image.rgba.size(), image.rgba.begin());
  stbi_image_free(data);
  return image;
}

ImageDifference compare_images(const Image& expected, const Image& actual, int tolerance) {
  ImageDifference d;
  if (expected.width != actual.width || expected.height != actual.height) {
    d.same_size = false;
    d.share = 1;
    return d;
  }
  d.diff = Image(expected.width, expected.height);
  for (int y = 0; y < expected.height; ++y) {
    for (int x = 0; x < expected.width; ++x) {
      const uint8_t* e = expected.pixel(x, y);
      const uint8_t* a = actual.pixel(x, y);
      int largest = 0;
      for (int c = 0; c < 4; ++c) largest = std::max(largest, std::abs(int(e[c]) - int(a[c])));
      d.largest = std::max(d.largest, largest);
      uint8_t* out = d.diff.pixel(x, y);
      if (largest > tolerance) {
        ++d.differing;
        out[0] = 255, out[1] = 0, out[2] = 0;
      } else {
        // The expected picture, faint, so that the red pixels can be placed.
        const uint8_t grey = uint8_t(200 + (e[0] + e[1] + e[2]) / 3 * 55 / 255);
        out[0] = out[1] = out[2] = grey;
      }
      out[3] = 255;
    }
  }
  d.share = double(d.differing) / (double(expected.width) * expected.height);
  return d;
}

}  // namespace dw::render
