#include "render/image.h"

#include <png.h>

#include "sim/output_file.h"

#include <algorithm>
#include <cstdlib>

namespace dw::render {

// Encoded in memory rather than by png_image_write_to_file, which remove()s its path when a write
// fails -- a device node included. The bytes go through sim::OutputFile instead.
std::optional<std::vector<uint8_t>> encode_png(const Image& image, std::string* error) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = png_uint_32(image.width);
  png.height = png_uint_32(image.height);
  png.format = PNG_FORMAT_RGBA;
  png_alloc_size_t size = 0;
  if (png_image_write_get_memory_size(png, size, 0, image.rgba.data(), image.width * 4, nullptr)) {
    std::vector<uint8_t> bytes(size);
    if (png_image_write_to_memory(&png, bytes.data(), &size, 0, image.rgba.data(), image.width * 4, nullptr)) {
      bytes.resize(size);
      return bytes;
    }
  }
  if (error) *error = std::string("cannot encode the PNG: ") + png.message;
  png_image_free(&png);
  return std::nullopt;
}

bool write_png(const std::string& path, const Image& image, std::string* error) {
  const auto bytes = encode_png(image, error);
  if (!bytes) return false;
  std::string failed = sim::write_file(path, *bytes);
  if (error) *error = failed;
  return failed.empty();
}

std::optional<Image> read_png(const std::string& path, std::string* error) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (png_image_begin_read_from_file(&png, path.c_str())) {
    png.format = PNG_FORMAT_RGBA;
    Image image(int(png.width), int(png.height));
    if (png_image_finish_read(&png, nullptr, image.rgba.data(), image.width * 4, nullptr)) return image;
  }
  if (error) *error = "cannot read " + path + ": " + png.message;
  png_image_free(&png);
  return std::nullopt;
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
