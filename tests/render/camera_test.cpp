#include "render/camera.h"

#include <gtest/gtest.h>

#include "tests/render/test_scenes.h"

#include "render/annotations.h"

namespace dw::render {
namespace {

// Every corner of every module lands inside the region, and the ensemble spans most of it in at
// least one direction (the camera is fitted, not merely far away).
void expect_fitted(const Scene& scene, int width, int height, const Region& region) {
  const Camera camera = make_camera(scene, width, height, region);
  const glm::mat4 vp = view_projection(camera, width, height, region);
  glm::vec2 lo(1e9f), hi(-1e9f);
  for (const SceneModule& m : scene.modules)
    for (int i = 0; i < 8; ++i) {
      const auto& p = m.pose.position;
      const glm::vec3 corner(p[0] + ((i & 1) ? 0.5f : -0.5f), p[1] + ((i & 2) ? 0.5f : -0.5f),
                             p[2] + ((i & 4) ? 0.5f : -0.5f));
      const auto at = project(vp, corner, width, height);
      ASSERT_TRUE(at.has_value());
      lo = glm::min(lo, *at);
      hi = glm::max(hi, *at);
    }
  EXPECT_GE(lo.x, region.left * width - 0.5f);
  EXPECT_LE(hi.x, region.right * width + 0.5f);
  EXPECT_GE(lo.y, region.top * height - 0.5f);
  EXPECT_LE(hi.y, region.bottom * height + 0.5f);
  const float fill_x = (hi.x - lo.x) / ((region.right - region.left) * width);
  const float fill_y = (hi.y - lo.y) / ((region.bottom - region.top) * height);
  EXPECT_GT(std::max(fill_x, fill_y), 0.9f);
}

TEST(Camera, FitsACubeIntoTheWholeImage) { expect_fitted(test::block(10, 10, 10), 1280, 720, Region{}); }

TEST(Camera, FitsAFlatSheetIntoARegionLeftOfAndBelowTheAnnotations) {
  expect_fitted(test::block(12, 10, 1), 1280, 720, Region{0.15f, 0.1f, 0.98f, 0.97f});
}

TEST(Camera, FitsALineAndATallImage) {
  expect_fitted(test::block(30, 1, 1), 400, 900, Region{});
  expect_fitted(test::block(1, 1, 1), 640, 360, Region{});
}

TEST(Camera, AFlatEnsembleIsSeenFromHigherUp) {
  auto elevation = [](const Camera& c) {
    const glm::vec3 d = glm::normalize(c.eye - c.target);
    return std::asin(d.z);
  };
  EXPECT_GT(elevation(make_camera(test::block(8, 8, 1), 800, 600, {})),
            elevation(make_camera(test::block(8, 8, 8), 800, 600, {})));
}

TEST(Camera, TheScenarioCameraWins) {
  Scene s = test::block(3, 3, 3);
  s.camera_eye = sim::Vec3{10, -20, 30};
  s.camera_target = sim::Vec3{1, 2, 3};
  const Camera c = make_camera(s, 800, 600, {});
  EXPECT_EQ(c.eye, glm::vec3(10, -20, 30));
  EXPECT_EQ(c.target, glm::vec3(1, 2, 3));
  // Without a target it looks at the middle of the ensemble.
  s.camera_target.reset();
  EXPECT_EQ(make_camera(s, 800, 600, {}).target, glm::vec3(1, 1, 1));
}

}  // namespace
}  // namespace dw::render
