// Images the renderer reads back, as PNG files, and how two of them differ (the golden-image
// tests, docs/design.md §9).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace dw::render {

// 8-bit RGBA, rows top to bottom.
struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;  // width * height * 4

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgba(size_t(w) * h * 4, 0) {}
  uint8_t* pixel(int x, int y) { return &rgba[(size_t(y) * width + x) * 4]; }
  const uint8_t* pixel(int x, int y) const { return &rgba[(size_t(y) * width + x) * 4]; }
};

// The image as a PNG file's bytes (libpng), or nothing (and `error` set).
std::optional<std::vector<uint8_t>> encode_png(const Image& image, std::string* error = nullptr);
// Writes a PNG through sim::OutputFile (a failed write leaves any old file as it was); false (and
// `error` set) when the file cannot be written.
bool write_png(const std::string& path, const Image& image, std::string* error = nullptr);
// Reads a PNG as RGBA, or nothing (and `error` set).
std::optional<Image> read_png(const std::string& path, std::string* error = nullptr);

struct ImageDifference {
  bool same_size = true;
  uint64_t differing = 0;  // pixels whose largest channel difference exceeds the tolerance
  double share = 0;        // differing / pixels
  int largest = 0;         // the largest channel difference anywhere
  Image diff;              // the expected image faded to grey, differing pixels in red
};

// Compares two images pixel by pixel; a pixel differs when some channel differs by more than
// `tolerance` (0..255).
ImageDifference compare_images(const Image& expected, const Image& actual, int tolerance);

}  // namespace dw::render
