#include "render/annotations.h"

#include <gtest/gtest.h>

namespace dw::render {
namespace {

const FontAtlas& font() {
  static const FontAtlas atlas = std::get<FontAtlas>(FontAtlas::bake(DWATCH_FONT_FILE, 20));
  return atlas;
}

Scene three_in_a_row() {
  Scene s;
  for (uint32_t i = 0; i < 3; ++i) {
    SceneModule m;
    m.id = i;
    m.pose.position = {float(i), 0, 0};
    s.modules.push_back(m);
  }
  s.title = "scene";
  return s;
}

TEST(Project, MapsClipSpaceToPixelsWithYDown) {
  const glm::mat4 identity(1.0f);
  EXPECT_EQ(*project(identity, {0, 0, 0}, 200, 100), glm::vec2(100, 50));
  EXPECT_EQ(*project(identity, {-1, 1, 0}, 200, 100), glm::vec2(0, 0));
  EXPECT_EQ(*project(identity, {1, -1, 0}, 200, 100), glm::vec2(200, 100));
  glm::mat4 behind(1.0f);
  behind[3][3] = -1;  // w < 0: behind the camera
  EXPECT_FALSE(project(behind, {0, 0, 0}, 200, 100).has_value());
}

// A module out of the picture is pointed at from the edge on its side, in from the edge; one in
// it is not; one behind the camera is pointed at on the side it lies.
TEST(EdgePointer, PointsFromTheEdgeTowardsWhatLeftThePicture) {
  const glm::mat4 identity(1.0f);  // x, y in [-1, 1] show; w = 1
  EXPECT_FALSE(edge_pointer(identity, {0.5f, 0.5f, 0}, 200, 100, 10));
  const auto right = edge_pointer(identity, {3, 0, 0}, 200, 100, 10);
  ASSERT_TRUE(right);
  EXPECT_FLOAT_EQ(right->at.x, 190);
  EXPECT_FLOAT_EQ(right->at.y, 50);
  EXPECT_FLOAT_EQ(right->toward.x, 1);
  const auto above_left = edge_pointer(identity, {-2, 4, 0}, 200, 100, 10);
  ASSERT_TRUE(above_left);
  EXPECT_FLOAT_EQ(above_left->at.y, 10) << "the top edge is met first";
  EXPECT_LT(above_left->at.x, 100);
  EXPECT_GT(above_left->at.x, 10);
  EXPECT_LT(above_left->toward.y, 0) << "y down: up is negative";
  glm::mat4 behind(1.0f);
  behind[3][3] = -1;  // w = -1: behind the camera, projected mirrored
  const auto back = edge_pointer(behind, {0.5f, 0, 0}, 200, 100, 10);
  ASSERT_TRUE(back) << "behind the camera never shows";
  EXPECT_FLOAT_EQ(back->at.x, 190) << "it lies to the right";
}

TEST(ViewRegion, LeavesRoomForTheTitleTheGroupLineAndTheLegend) {
  Scene s = three_in_a_row();
  const Region plain = view_region(s, font(), 1000, 600);
  EXPECT_EQ(plain.left, 0);
  EXPECT_GT(plain.top, 0);
  s.groups.push_back({"w", 0, {"a"}, {1}});
  const Region grouped = view_region(s, font(), 1000, 600);
  EXPECT_GT(grouped.top, plain.top);
  s.legend = {"isLeader", false, {{Color{1, 0, 0}, "0"}, {Color{0, 1, 0}, "1"}}};
  const Region legend = view_region(s, font(), 1000, 600);
  EXPECT_GT(legend.left, 0.05f);
  EXPECT_LT(legend.left, 0.4f);
}

// Vertices of the overlay's solid shapes in the colour of the slot links.
size_t link_coloured(const Overlay& o) {
  size_t n = 0;
  for (const OverlayVertex& v : o.vertices())
    if (v.r > 0.8f && v.g < 0.2f && v.b < 0.2f && v.u == font().white_u()) ++n;
  return n;
}

TEST(Annotate, LinksAndLabelsEachSlotOfEachGroup) {
  Scene s = three_in_a_row();
  const glm::mat4 vp = view_projection(make_camera(s, 800, 600, {}), 800, 600, {});
  Overlay bare(font());
  annotate(bare, s, vp, 800, 600);
  EXPECT_EQ(link_coloured(bare), 0u);

  s.groups.push_back({"w", 3, {"a", "b", "c"}, {0, 1, 2}});
  Overlay one(font());
  annotate(one, s, vp, 800, 600);
  const size_t per_group = link_coloured(one);
  EXPECT_GT(per_group, 0u);
  // A second group adds as much again; a group naming a module not in the scene draws nothing of
  // that slot.
  s.groups.push_back({"w", 3, {"a", "b", "c"}, {2, 1, 0}});
  Overlay two(font());
  annotate(two, s, vp, 800, 600);
  EXPECT_EQ(link_coloured(two), 2 * per_group);
  s.groups.back().modules = {2, 1, 77};
  Overlay missing(font());
  annotate(missing, s, vp, 800, 600);
  EXPECT_LT(link_coloured(missing), 2 * per_group);
  EXPECT_GT(link_coloured(missing), per_group);
}

// Labels never pile up: three modules a pixel apart on screen (a group among 11,000 modules) get
// three labels that do not overlap, each near its module; labels with room stay above theirs.
TEST(PlaceLabels, SpreadsTheLabelsOfModulesThatShowOnOneSpot) {
  const float r = 14;
  const std::vector<std::optional<glm::vec2>> tops{glm::vec2(400, 300), glm::vec2(401, 300), glm::vec2(401, 301)};
  std::vector<std::optional<glm::vec2>> wanted;
  for (const auto& t : tops) wanted.push_back(*t + glm::vec2(0, -20));
  const auto placed = place_labels(tops, wanted, r);
  ASSERT_EQ(placed.size(), 3u);
  EXPECT_EQ(placed[0], wanted[0]);
  for (size_t i = 0; i < 3; ++i) {
    ASSERT_TRUE(placed[i]);
    EXPECT_LT(glm::distance(*placed[i], *tops[i]), 8 * r) << "label " << i << " strays from its module";
    for (size_t j = i + 1; j < 3; ++j) EXPECT_GE(glm::distance(*placed[i], *placed[j]), 2 * r) << i << " " << j;
  }
  const std::vector<std::optional<glm::vec2>> apart{glm::vec2(100, 300), glm::vec2(300, 300)};
  const std::vector<std::optional<glm::vec2>> above{glm::vec2(100, 280), glm::vec2(300, 280)};
  EXPECT_EQ(place_labels(apart, above, r), above);
  // A label keeps off the caption: wanted on it, it moves around its module, clear of the box.
  const std::vector<Box> caption{{glm::vec2(10, 20), glm::vec2(300, 40)}};
  const auto kept = place_labels({glm::vec2(200, 70)}, {glm::vec2(200, 35)}, r, caption);
  ASSERT_TRUE(kept[0]);
  EXPECT_GE(glm::distance(glm::clamp(*kept[0], caption[0].min, caption[0].max), *kept[0]), r) << "over the caption";
  EXPECT_LT(glm::distance(*kept[0], glm::vec2(200, 70)), 8 * r);
  // A module off screen has no label.
  EXPECT_FALSE(place_labels({std::nullopt}, {glm::vec2(1, 1)}, r)[0]);
}

}  // namespace
}  // namespace dw::render
