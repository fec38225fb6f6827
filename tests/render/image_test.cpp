#include "render/image.h"

#include <gtest/gtest.h>

#include <filesystem>

namespace dw::render {
namespace {

Image pattern(int w, int h) {
  Image image(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      uint8_t* p = image.pixel(x, y);
      p[0] = uint8_t(x * 7), p[1] = uint8_t(y * 13), p[2] = uint8_t(x ^ y), p[3] = 255;
    }
  return image;
}

TEST(Png, WritesAndReadsBackEveryPixelTopRowFirst) {
  const auto path = std::filesystem::temp_directory_path() / ("dwatch_png_" + std::to_string(::getpid()) + ".png");
  const Image image = pattern(37, 21);
  ASSERT_TRUE(write_png(path.string(), image));
  const auto read = read_png(path.string());
  std::filesystem::remove(path);
  ASSERT_TRUE(read.has_value());
  EXPECT_EQ(read->width, 37);
  EXPECT_EQ(read->height, 21);
  EXPECT_EQ(read->rgba, image.rgba);
}

TEST(Png, MissingFilesAndBadPathsAreErrors) {
  std::string error;
  EXPECT_FALSE(read_png("/nonexistent/x.png", &error).has_value());
  EXPECT_NE(error.find("/nonexistent/x.png"), std::string::npos);
  EXPECT_FALSE(write_png("/nonexistent/dir/x.png", pattern(2, 2), &error));
  EXPECT_NE(error.find("cannot write"), std::string::npos);
}

TEST(CompareImages, CountsPixelsBeyondTheToleranceAndMarksThemRed) {
  const Image expected = pattern(10, 10);
  Image actual = expected;
  actual.pixel(3, 4)[1] = uint8_t(actual.pixel(3, 4)[1] + 40);  // beyond
  actual.pixel(5, 5)[0] = uint8_t(actual.pixel(5, 5)[0] + 5);   // within
  const ImageDifference d = compare_images(expected, actual, 8);
  EXPECT_TRUE(d.same_size);
  EXPECT_EQ(d.differing, 1u);
  EXPECT_DOUBLE_EQ(d.share, 0.01);
  EXPECT_EQ(d.largest, 40);
  EXPECT_EQ(d.diff.pixel(3, 4)[0], 255);
  EXPECT_EQ(d.diff.pixel(3, 4)[1], 0);
  EXPECT_EQ(d.diff.pixel(5, 5)[0], d.diff.pixel(5, 5)[1]);  // grey: not marked
  EXPECT_EQ(compare_images(expected, expected, 0).differing, 0u);
}

TEST(CompareImages, DifferentSizesDifferEverywhere) {
  const ImageDifference d = compare_images(pattern(4, 4), pattern(4, 5), 255);
  EXPECT_FALSE(d.same_size);
  EXPECT_EQ(d.share, 1);
}

}  // namespace
}  // namespace dw::render
