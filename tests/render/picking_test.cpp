#include "render/picking.h"

#include <gtest/gtest.h>

#include <cmath>

#include "render/annotations.h"
#include "render/camera.h"
#include "test_scenes.h"

namespace dw::render {
namespace {

struct View {
  glm::mat4 vp;
  int width = 640, height = 480;
};

View fitted(const Scene& scene) {
  View v;
  v.vp = view_projection(make_camera(scene, v.width, v.height, {}), v.width, v.height, {});
  return v;
}

glm::vec2 pixel_of(const View& v, glm::vec3 p) { return *project(v.vp, p, v.width, v.height); }

TEST(Picking, EveryModuleOfALineIsFoundAtItsOwnCentre) {
  const Scene scene = test::block(6, 1, 1);
  const View v = fitted(scene);
  for (const SceneModule& m : scene.modules) {
    const auto& p = m.pose.position;
    EXPECT_EQ(pick(scene, v.vp, v.width, v.height, pixel_of(v, {p[0], p[1], p[2]})), m.id) << "module " << m.id;
  }
}

TEST(Picking, TheNearestOfAStackedColumnWins) {
  // Seen from above and in front, the ray through the top face of a column hits the top module
  // first; the modules under it are farther along the same ray.
  const Scene scene = test::block(1, 1, 4);
  const View v = fitted(scene);
  EXPECT_EQ(pick(scene, v.vp, v.width, v.height, pixel_of(v, {0, 0, 3.5f})), sim::ModuleId(3));
  EXPECT_EQ(pick(scene, v.vp, v.width, v.height, pixel_of(v, {0, 0, 0})), sim::ModuleId(0));
}

TEST(Picking, EmptySpaceAndOutsideTheImageHitNothing) {
  const Scene scene = test::block(3, 3, 1);
  const View v = fitted(scene);
  EXPECT_EQ(pick(scene, v.vp, v.width, v.height, {2, 2}), std::nullopt);
  EXPECT_EQ(pick(scene, v.vp, v.width, v.height, pixel_of(v, {1, 6, 0})), std::nullopt);
  EXPECT_EQ(pick(scene, v.vp, 0, 0, {0, 0}), std::nullopt);
}

TEST(Picking, ARotatedBoxIsTestedInItsOwnFrame) {
  // A box turned 45 degrees about z reaches 0.707 along x: a point 0.6 out hits it, and misses it
  // when it is not turned.
  Scene scene = test::block(1, 1, 1);
  const View v = fitted(scene);
  const glm::vec2 beside = pixel_of(v, {0.6f, 0, 0});
  EXPECT_EQ(pick(scene, v.vp, v.width, v.height, beside), std::nullopt);
  const float s = std::sin(glm::radians(22.5f)), c = std::cos(glm::radians(22.5f));
  scene.modules[0].pose.orientation = {0, 0, s, c};
  EXPECT_EQ(pick(scene, v.vp, v.width, v.height, beside), sim::ModuleId(0));
}

TEST(Picking, SpheresAreRound) {
  // Seen from straight above, the corner of a unit box's top face lies outside the sphere of the
  // same size.
  Scene scene = test::block(1, 1, 1);
  Camera above;
  above.eye = {0, 0, 40};
  above.up = {0, 1, 0};
  View v;
  v.vp = view_projection(above, v.width, v.height, {});
  const glm::vec2 corner = pixel_of(v, {0.45f, 0.45f, 0.5f});
  EXPECT_EQ(pick(scene, v.vp, v.width, v.height, corner), sim::ModuleId(0));
  scene.module_shape = Shape::Sphere;
  EXPECT_EQ(pick(scene, v.vp, v.width, v.height, corner), std::nullopt);
}

}  // namespace
}  // namespace dw::render
