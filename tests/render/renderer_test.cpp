// The renderer through a real OSMesa context: what lands in the pixels.
#include "render/renderer.h"

#include <gtest/gtest.h>

#include "tests/render/test_scenes.h"

#include "render/osmesa_context.h"

namespace dw::render {
namespace {

class RendererTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    auto made = OsMesaContext::create();
    ASSERT_TRUE(std::holds_alternative<std::unique_ptr<OsMesaContext>>(made)) << std::get<std::string>(made);
    context_ = std::get<0>(std::move(made)).release();
    renderer_ = new Renderer(context_->gl());
  }
  static void TearDownTestSuite() {
    delete renderer_;
    delete context_;
  }
  static OsMesaContext* context_;
  static Renderer* renderer_;
};
OsMesaContext* RendererTest::context_ = nullptr;
Renderer* RendererTest::renderer_ = nullptr;

// Pixels in a rectangle for which `test(r, g, b)` holds.
template <typename Test>
int count(const Image& image, int x0, int y0, int x1, int y1, Test test) {
  int n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const uint8_t* p = image.pixel(x, y);
      if (test(p[0], p[1], p[2])) ++n;
    }
  return n;
}

bool greenish(int r, int g, int b) { return g > r + 60 && g > b + 60; }
bool link_red(int r, int g, int b) { return r > 170 && g < 70 && b < 80; }

TEST_F(RendererTest, DrawsTheModulesInTheirColourOnTheBackground) {
  const Image image = renderer_->render(test::block(1, 1, 1, {0.1f, 0.8f, 0.2f}), 320, 240);
  ASSERT_EQ(image.width, 320);
  ASSERT_EQ(image.height, 240);
  EXPECT_TRUE(greenish(image.pixel(160, 120)[0], image.pixel(160, 120)[1], image.pixel(160, 120)[2]));
  EXPECT_GT(count(image, 0, 0, 320, 240, greenish), 320 * 240 / 5);  // the fitted module fills the view
  for (size_t i = 3; i < image.rgba.size(); i += 4) ASSERT_EQ(image.rgba[i], 255);
}

TEST_F(RendererTest, ReadsBackTheRightWayUp) {
  // The title is written at the top left: dark text pixels there, none in the bottom rows.
  Scene s = test::block(1, 1, 1, {0.1f, 0.8f, 0.2f});
  s.title = "WWWWWWWWWWWW";
  const Image image = renderer_->render(s, 400, 300);
  auto ink = [](int r, int g, int b) { return r < 90 && g < 90 && b < 90; };
  EXPECT_GT(count(image, 0, 0, 200, 30, ink), 40);
  EXPECT_EQ(count(image, 0, 270, 200, 300, ink), 0);
}

TEST_F(RendererTest, AnEmptySceneStillShowsItsTitleOnTheBackground) {
  Scene s;
  s.title = "WWWWWWWWWWWW";
  const Image image = renderer_->render(s, 400, 300);
  auto ink = [](int r, int g, int b) { return r < 90 && g < 90 && b < 90; };
  EXPECT_GT(count(image, 0, 0, 200, 30, ink), 40);
  const uint8_t* corner = image.pixel(399, 299);
  EXPECT_GT(corner[0], 200);
}

TEST_F(RendererTest, AHighlightedGroupIsOutlinedAndShowsThroughTheOthers) {
  // The middle module of a 5x5x5 cube is hidden from every side, until it is highlighted.
  Scene s = test::block(5, 5, 5, {0.55f, 0.63f, 0.72f});
  const sim::ModuleId middle = 2 + 5 * (2 + 5 * 2);
  s.modules[middle].color = {0.1f, 0.8f, 0.2f};
  const Image plain = renderer_->render(s, 400, 300);
  EXPECT_EQ(count(plain, 0, 0, 400, 300, greenish), 0);
  EXPECT_EQ(count(plain, 0, 0, 400, 300, link_red), 0);

  s.modules[middle].highlighted = true;
  s.groups.push_back({"w", 0, {"a"}, {middle}});
  const Image highlighted = renderer_->render(s, 400, 300);
  EXPECT_GT(count(highlighted, 0, 0, 400, 300, greenish), 100);
  EXPECT_GT(count(highlighted, 0, 0, 400, 300, link_red), 100);
}

TEST_F(RendererTest, TheSameSceneGivesTheSamePixels) {
  Scene s = test::block(3, 3, 3, {0.9f, 0.5f, 0.1f});
  s.groups.push_back({"w", 0, {"a", "b"}, {0, 1}});
  s.modules[0].highlighted = s.modules[1].highlighted = true;
  const Image a = renderer_->render(s, 300, 200);
  const Image b = renderer_->render(test::block(2, 2, 2, {0, 0, 1}), 640, 480);  // a different size in between
  const Image c = renderer_->render(s, 300, 200);
  EXPECT_EQ(a.rgba, c.rgba);
  EXPECT_NE(b.width, a.width);
}

// camera() is the camera draw() uses: set on the scene, it draws the same picture, whether the
// scene set none (fitted), a target only, or both.
TEST_F(RendererTest, TheCameraItUsesDrawsTheSamePictureWhenSetOnTheScene) {
  Scene s = test::block(4, 3, 2, {0.9f, 0.5f, 0.1f});
  s.title = "camera";
  s.modules[0].highlighted = s.modules[1].highlighted = true;
  s.groups.push_back({"w", 0, {"a", "b"}, {0, 1}});
  for (const std::optional<sim::Vec3> target : {std::optional<sim::Vec3>{}, std::optional<sim::Vec3>{{0, 0, 0}}}) {
    s.camera_eye.reset();
    s.camera_target = target;
    const Image as_set = renderer_->render(s, 320, 200);
    const Camera c = renderer_->camera(s, 320, 200);
    s.camera_eye = sim::Vec3{c.eye.x, c.eye.y, c.eye.z};
    s.camera_target = sim::Vec3{c.target.x, c.target.y, c.target.z};
    EXPECT_EQ(renderer_->render(s, 320, 200).rgba, as_set.rgba);
  }
  // An eye and a target set are the camera's, as given.
  s.camera_eye = sim::Vec3{9, -7, 6};
  s.camera_target = sim::Vec3{1, 1, 0};
  const Camera given = renderer_->camera(s, 320, 200);
  EXPECT_EQ(given.eye, glm::vec3(9, -7, 6));
  EXPECT_EQ(given.target, glm::vec3(1, 1, 0));
}

// A moving frame (the window while the camera turns or play runs) skips the edge smoothing and
// draws the modules around a group opaque, unsorted, leaving out those enclosed on six sides: the
// group must still show through, outlined, and the rest look as the still frame does.
TEST_F(RendererTest, AMovingFrameStillShowsTheGroupThroughTheOthers) {
  Scene s = test::block(5, 5, 5, {0.55f, 0.63f, 0.72f});
  const sim::ModuleId middle = 2 + 5 * (2 + 5 * 2);
  s.modules[middle].color = {0.1f, 0.8f, 0.2f};
  const Image plain = renderer_->render(s, 400, 300, RenderQuality::Moving);
  EXPECT_EQ(count(plain, 0, 0, 400, 300, greenish), 0);  // enclosed, left out or not: unseen

  s.modules[middle].highlighted = true;
  s.groups.push_back({"w", 0, {"a"}, {middle}});
  const Image moving = renderer_->render(s, 400, 300, RenderQuality::Moving);
  EXPECT_GT(count(moving, 0, 0, 400, 300, greenish), 100);
  EXPECT_GT(count(moving, 0, 0, 400, 300, link_red), 100);
}

TEST_F(RendererTest, AMovingFrameLooksLikeTheStillOne) {
  Scene s = test::block(6, 5, 4, {0.9f, 0.5f, 0.1f});
  const Image still = renderer_->render(s, 400, 300);
  const Image moving = renderer_->render(s, 400, 300, RenderQuality::Moving);
  const ImageDifference d = compare_images(still, moving, 48);
  EXPECT_TRUE(d.same_size);
  EXPECT_GT(d.differing, 0) << "the edges are not smoothed";
  EXPECT_LT(d.share, 0.02) << d.differing << " pixels differ by more than 48";
}

// Drawing a moving frame leaves nothing behind: the still frame after is the one before.
TEST_F(RendererTest, TheStillFrameAfterAMovingOneIsTheSame) {
  Scene s = test::block(4, 4, 3, {0.2f, 0.4f, 0.9f});
  s.groups.push_back({"w", 0, {"a", "b"}, {5, 6}});
  s.modules[5].highlighted = s.modules[6].highlighted = true;
  const Image before = renderer_->render(s, 320, 200);
  const Image moving = renderer_->render(s, 320, 200, RenderQuality::Moving);
  const Image after = renderer_->render(s, 320, 200);
  EXPECT_EQ(before.rgba, after.rgba);
  EXPECT_NE(moving.rgba, before.rgba);
}

TEST_F(RendererTest, ImagesOutOfRangeAreRefused) {
  EXPECT_THROW(renderer_->render(test::block(1, 1, 1, {}), 0, 100), RenderError);
  EXPECT_THROW(renderer_->render(test::block(1, 1, 1, {}), renderer_->max_size() + 1, 100), RenderError);
}

TEST(OsMesaContext, IsGl33CoreOrNewer) {
  auto made = OsMesaContext::create();
  ASSERT_TRUE(std::holds_alternative<std::unique_ptr<OsMesaContext>>(made));
  const Gl& gl = std::get<0>(made)->gl();
  GLint major = 0, minor = 0, profile = 0;
  gl.GetIntegerv(GL_MAJOR_VERSION, &major);
  gl.GetIntegerv(GL_MINOR_VERSION, &minor);
  gl.GetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  EXPECT_GE(major * 10 + minor, 33);
  EXPECT_TRUE(profile & GL_CONTEXT_CORE_PROFILE_BIT);
}

}  // namespace
}  // namespace dw::render
