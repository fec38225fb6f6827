#include "render/palette.h"

#include <gtest/gtest.h>

#include <set>
#include <tuple>
#include <vector>

namespace dw::render {
namespace {

TEST(ColorScale, SmallRangesAreCategoricalWithOneDistinctColourPerValue) {
  const std::vector<int64_t> values = {3, 5, 4, 12, 3};  // 3..12: ten values
  const ColorScale scale("v", values);
  EXPECT_TRUE(scale.categorical());
  std::set<std::tuple<float, float, float>> seen;
  for (int64_t v = 3; v <= 12; ++v) seen.insert({scale.color(v).r, scale.color(v).g, scale.color(v).b});
  EXPECT_EQ(seen.size(), 10u);
  const Legend legend = scale.legend();
  EXPECT_EQ(legend.title, "v");
  EXPECT_FALSE(legend.gradient);
  ASSERT_EQ(legend.entries.size(), 10u);
  EXPECT_EQ(legend.entries.front().label, "3");
  EXPECT_EQ(legend.entries.back().label, "12");
  EXPECT_EQ(legend.entries[2].color, scale.color(5));
}

TEST(ColorScale, WideRangesAreAGradientFromTheSmallestToTheLargestValue) {
  const std::vector<int64_t> values = {-20, 0, 80};
  const ColorScale scale("dist", values);
  EXPECT_FALSE(scale.categorical());
  EXPECT_EQ(scale.color(-20), gradient_color(0));
  EXPECT_EQ(scale.color(80), gradient_color(1));
  // Viridis grows lighter from its dark purple end to its yellow end.
  auto light = [](Color c) { return 0.3f * c.r + 0.59f * c.g + 0.11f * c.b; };
  EXPECT_LT(light(scale.color(-20)), light(scale.color(30)));
  EXPECT_LT(light(scale.color(30)), light(scale.color(80)));
  const Legend legend = scale.legend();
  EXPECT_TRUE(legend.gradient);
  ASSERT_EQ(legend.entries.size(), 5u);
  EXPECT_EQ(legend.entries[0].label, "-20");
  EXPECT_EQ(legend.entries[2].label, "30");
  EXPECT_EQ(legend.entries[4].label, "80");
}

TEST(ColorScale, ASingleValueOrNoneIsOneCategory) {
  const std::vector<int64_t> one = {7, 7};
  EXPECT_EQ(ColorScale("v", one).legend().entries.size(), 1u);
  EXPECT_EQ(ColorScale("v", {}).legend().entries.size(), 1u);
}

TEST(Palette, GradientIsClampedAndCategoriesCycle) {
  EXPECT_EQ(gradient_color(-1), gradient_color(0));
  EXPECT_EQ(gradient_color(2), gradient_color(1));
  EXPECT_EQ(category_color(0), category_color(10));
  EXPECT_NE(category_color(0), category_color(1));
}

}  // namespace
}  // namespace dw::render
