#include "render/camera.h"

#include <gtest/gtest.h>

#include <cmath>

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

// Every module's centre projects inside the picture through a finite matrix.
void expect_in_view(const Scene& s) {
  const Camera c = make_camera(s, 640, 480, {});
  const glm::mat4 vp = view_projection(c, 640, 480, {});
  for (const SceneModule& m : s.modules) {
    const auto at = project(vp, glm::vec3(m.pose.position[0], m.pose.position[1], m.pose.position[2]), 640, 480);
    ASSERT_TRUE(at.has_value());
    EXPECT_TRUE(std::isfinite(at->x) && std::isfinite(at->y));
    EXPECT_GE(at->x, 0);
    EXPECT_LE(at->x, 640);
    EXPECT_GE(at->y, 0);
    EXPECT_LE(at->y, 480);
  }
}

TEST(Camera, StraightDownSeesAFlatLatticeWithYUp) {
  // The natural view of a 2-D lattice: z cannot be the picture's up then.
  Scene s = test::block(12, 8, 1);
  s.camera_eye = sim::Vec3{5.5f, 3.5f, 30};
  s.camera_target = sim::Vec3{5.5f, 3.5f, 0};
  expect_in_view(s);
  const Camera c = make_camera(s, 640, 480, {});
  const glm::mat4 vp = view_projection(c, 640, 480, {});
  // x grows to the right and y upwards, as on the lattice's plan.
  const auto origin = project(vp, glm::vec3(0, 0, 0), 640, 480), x = project(vp, glm::vec3(1, 0, 0), 640, 480),
             y = project(vp, glm::vec3(0, 1, 0), 640, 480);
  EXPECT_GT(x->x, origin->x);
  EXPECT_LT(y->y, origin->y);  // picture rows grow downwards
  // And straight up from below.
  s.camera_eye = sim::Vec3{5.5f, 3.5f, -30};
  expect_in_view(s);
}

TEST(Camera, AnEyeOnItsTargetFallsBackToTheFittedView) {
  Scene s = test::block(3, 3, 3);
  s.camera_eye = sim::Vec3{1, 1, 1};  // the ensemble's centre, which is the default target
  expect_in_view(s);
  EXPECT_NE(make_camera(s, 640, 480, {}).eye, glm::vec3(1, 1, 1));
}

// A camera the user gave that would draw a blank picture is told apart from one that sees the
// ensemble: looking away, from behind, or from so far that it is under two pixels.
TEST(Camera, ACameraThatMissesTheEnsembleSaysWhy) {
  Scene s = test::block(12, 8, 1);
  EXPECT_EQ(camera_misses(s, 640, 480), "") << "a fitted camera";
  s.camera_eye = sim::Vec3{5.5f, 3.5f, 30};
  s.camera_target = sim::Vec3{5.5f, 3.5f, 0};
  EXPECT_EQ(camera_misses(s, 640, 480), "") << "straight down";
  s.camera_target = sim::Vec3{5.5f, 3.5f, 100};  // straight up, from above the sheet
  EXPECT_NE(camera_misses(s, 640, 480).find("sees none of the modules"), std::string::npos);
  s.camera_target = sim::Vec3{200, 3.5f, 30};  // level, off to the side
  EXPECT_NE(camera_misses(s, 640, 480).find("sees none of the modules"), std::string::npos);
  s.camera_eye = sim::Vec3{5.5f, 3.5f, 9000};  // on the axis, but 9,000 module sizes up
  s.camera_target = sim::Vec3{5.5f, 3.5f, 0};
  EXPECT_NE(camera_misses(s, 640, 480).find("under 2 pixels"), std::string::npos);
  s.camera_eye = sim::Vec3{5.5f, 3.5f, 900};  // 12 modules across from 900: about 17 pixels
  EXPECT_EQ(camera_misses(s, 640, 480), "");
  s.camera_eye = sim::Vec3{-3, 3.5f, 5};  // looking past the sheet's corner: part of it shows
  s.camera_target = sim::Vec3{0, 12, 0};
  EXPECT_EQ(camera_misses(s, 640, 480), "");
}

// An eye inside a module draws the inside of its faces: refused, naming the module. Just outside
// its face, the module fills the view and is drawn.
TEST(Camera, AnEyeInsideAModuleIsRefusedNamingIt) {
  Scene s = test::block(4, 4, 1);
  s.camera_target = sim::Vec3{3, 3, 0};
  s.camera_eye = sim::Vec3{0.1f, 0.1f, 0.1f};
  EXPECT_NE(camera_misses(s, 640, 480).find("is inside module 0 "), std::string::npos) << camera_misses(s, 640, 480);
  s.camera_eye = sim::Vec3{2.3f, 1.2f, 0.4f};  // module 6, at (2, 1, 0)
  EXPECT_NE(camera_misses(s, 640, 480).find("is inside module 6 "), std::string::npos) << camera_misses(s, 640, 480);
  s.camera_eye = sim::Vec3{1.5f, 1.5f, 0.8f};  // above the sheet, between four modules
  EXPECT_EQ(camera_misses(s, 640, 480), "");
  // A module turned 45 degrees about z reaches 0.707 along x: an eye at 0.6 is inside it.
  s.modules[0].pose.orientation = {0, 0, std::sin(0.3927f), std::cos(0.3927f)};
  s.camera_eye = sim::Vec3{-0.6f, 0, 0};
  s.camera_target = sim::Vec3{-5, 0, 0};
  EXPECT_NE(camera_misses(s, 640, 480).find("is inside module 0 "), std::string::npos) << camera_misses(s, 640, 480);
}

// A target given alone moves the fitted camera, whose eye is derived from it (make_camera): that
// camera is checked too, as a target far off draws nothing.
TEST(Camera, ATargetAloneIsCheckedWithTheEyeFittedToIt) {
  Scene s = test::block(12, 8, 1);
  s.camera_target = sim::Vec3{5.5f, 3.5f, 0};  // the sheet's middle
  EXPECT_EQ(camera_misses(s, 640, 480), "");
  s.camera_target = sim::Vec3{1e6f, 1e6f, 1e6f};
  EXPECT_NE(camera_misses(s, 640, 480).find("the camera at "), std::string::npos);
  s.camera_target = sim::Vec3{0, 0, -1000};
  EXPECT_NE(camera_misses(s, 640, 480).find("the camera at "), std::string::npos);
}

}  // namespace
}  // namespace dw::render
