#include "render/scene.h"

#include <gtest/gtest.h>

#include "render/palette.h"
#include "sim/model.h"

namespace dw::render {
namespace {

// One variable, set by the tests themselves.
class Still final : public sim::HostProgram {
 public:
  std::string_view name() const override { return "still"; }
  std::vector<sim::VariableSpec> variables() const override { return {{"v", 0}}; }
  void step(sim::ModuleContext&) const override {}
};

// A 3x2 square lattice with one variable per module.
struct Fixture {
  std::unique_ptr<sim::Model> model;
  sim::State state;

  explicit Fixture(std::vector<int64_t> values) {
    sim::Lattice lattice = sim::make_lattice({sim::LatticeKind::Square2d, {3, 2, 1}});
    std::vector<std::unique_ptr<const sim::HostProgram>> programs;
    programs.push_back(std::make_unique<Still>());
    model = std::get<0>(sim::build_model(std::move(lattice), std::move(programs), {}, 1));
    state.step = 1;
    state.values = std::move(values);
    state.present.assign(6, 1);
  }
};

TEST(BuildScene, LatticePositionsAndColoursByTheVariable) {
  Fixture f({0, 1, 1, 0, 2, 0});
  SceneSettings settings;
  settings.color_by = "v";
  settings.title = "t";
  const Scene scene = build_scene(*f.model, f.state, {}, settings);
  ASSERT_EQ(scene.modules.size(), 6u);
  const ColorScale scale("v", f.state.values);
  for (const SceneModule& m : scene.modules) {
    EXPECT_EQ(m.pose.position, f.model->lattice.position(m.id));
    EXPECT_EQ(m.color, scale.color(f.state.values[m.id]));
    EXPECT_FALSE(m.highlighted);
  }
  EXPECT_EQ(scene.legend.title, "v");
  EXPECT_EQ(scene.legend.entries.size(), 3u);
  EXPECT_FLOAT_EQ(scene.ground_z, f.model->lattice.position(0)[2] - 0.5f);
  EXPECT_EQ(scene.title, "t");
}

TEST(BuildScene, WithoutAVariableEveryModuleIsNeutralAndThereIsNoLegend) {
  Fixture f({0, 1, 1, 0, 2, 0});
  const Scene scene = build_scene(*f.model, f.state, {}, {});
  for (const SceneModule& m : scene.modules) EXPECT_EQ(m.color, kNeutralModule);
  EXPECT_TRUE(scene.legend.title.empty());
}

TEST(BuildScene, AbsentModulesAreLeftOutAndDoNotWidenTheScale) {
  Fixture f({0, 1, 1, 0, 99, 0});
  f.state.present[4] = 0;
  SceneSettings settings;
  settings.color_by = "v";
  const Scene scene = build_scene(*f.model, f.state, {}, settings);
  ASSERT_EQ(scene.modules.size(), 5u);
  for (const SceneModule& m : scene.modules) EXPECT_NE(m.id, 4u);
  EXPECT_FALSE(scene.legend.gradient);  // 0..1, not 0..99
  EXPECT_EQ(scene.legend.entries.size(), 2u);
}

TEST(BuildScene, GroupsMarkTheirModulesAndAreKeptInSlotOrder) {
  Fixture f({0, 1, 1, 0, 2, 0});
  const std::vector<SceneGroup> groups = {{"w", 1, {"a", "b"}, {4, 1}}};
  const Scene scene = build_scene(*f.model, f.state, groups, {});
  for (const SceneModule& m : scene.modules) EXPECT_EQ(m.highlighted, m.id == 4 || m.id == 1) << m.id;
  ASSERT_EQ(scene.groups.size(), 1u);
  EXPECT_EQ(scene.groups[0].modules, (std::vector<sim::ModuleId>{4, 1}));
}

TEST(BuildScene, PhysicalPosesAndPropsComeFromTheState) {
  Fixture f({0, 0, 0, 0, 0, 0});
  f.state.bodies.poses.resize(6);
  for (uint32_t m = 0; m < 6; ++m) f.state.bodies.poses.set(m, {.position = {float(m) * 2, 1, 3}});
  f.state.bodies.poses.set(2, {.position = {4, 1, 3}, .orientation = {0, 0, 0.7071068f, 0.7071068f}});
  f.state.bodies.prop_poses = {sim::Pose{{5, 6, 7}, {0, 0, 0, 1}}};
  SceneSettings settings;
  settings.module_shape = Shape::Sphere;
  settings.props = {SceneProp{Shape::Box, {2, 1, 1}, {}}};
  settings.ground_z = -4;
  const Scene scene = build_scene(*f.model, f.state, {}, settings);
  for (const SceneModule& m : scene.modules) EXPECT_EQ(m.pose, f.state.bodies.poses[m.id]);
  ASSERT_EQ(scene.props.size(), 1u);
  EXPECT_EQ(scene.props[0].pose.position, (sim::Vec3{5, 6, 7}));
  EXPECT_EQ(scene.props[0].size, (sim::Vec3{2, 1, 1}));
  EXPECT_EQ(scene.module_shape, Shape::Sphere);
  EXPECT_FLOAT_EQ(scene.ground_z, -4);
}

// A contact's point goes into the world through the frame of its first body: a module's own pose
// (turned a quarter about z here), a moving cluster's frame, the world's for a cluster latched to
// the ground, a prop's pose; and only when the settings ask for contacts.
TEST(BuildScene, ContactPointsAreInTheWorldThroughTheirFirstBodysFrame) {
  Fixture f({0, 0, 0, 0, 0, 0});
  f.state.bodies.poses.resize(6);
  f.state.bodies.poses.set(2, {.position = {4, 1, 3}, .orientation = {0, 0, 0.7071068f, 0.7071068f}});
  f.state.bodies.prop_poses = {sim::Pose{{5, 6, 7}, {0, 0, 0, 1}}};
  f.state.bodies.cluster_of.resize(6);
  for (uint32_t m = 0; m < 6; ++m) f.state.bodies.cluster_of.set(m, sim::kNoCluster);
  f.state.bodies.clusters = {sim::Cluster{.pose = {{10, 0, 0}, {0, 0, 0, 1}}},
                             sim::Cluster{.pose = {{20, 0, 0}, {0, 0, 0, 1}}, .anchored = true}};
  f.state.bodies.cluster_of.set(3, 0);
  f.state.bodies.cluster_of.set(4, 1);
  auto contact = [](uint32_t a) {
    return sim::ContactPoint{.a = a, .b = sim::kGroundContact, .local_a = {0.5f, 0, 0}, .normal = {0, 0, 1}};
  };
  f.state.bodies.contacts = {contact(2), contact(3), contact(4), contact(sim::contact_prop(0))};
  EXPECT_TRUE(build_scene(*f.model, f.state, {}, SceneSettings{}).contacts.empty());
  SceneSettings settings;
  settings.contacts = true;
  const Scene scene = build_scene(*f.model, f.state, {}, settings);
  ASSERT_EQ(scene.contacts.size(), 4u);
  auto near = [](sim::Vec3 x, sim::Vec3 y) {
    return std::abs(x[0] - y[0]) < 1e-5f && std::abs(x[1] - y[1]) < 1e-5f && std::abs(x[2] - y[2]) < 1e-5f;
  };
  EXPECT_TRUE(near(scene.contacts[0].point, {4, 1.5f, 3})) << "turned a quarter about z: +x goes to +y";
  EXPECT_TRUE(near(scene.contacts[1].point, {10.5f, 0, 0})) << "the cluster's frame";
  EXPECT_TRUE(near(scene.contacts[2].point, {0.5f, 0, 0})) << "latched: the world's frame";
  EXPECT_TRUE(near(scene.contacts[3].point, {5.5f, 6, 7})) << "the prop's pose";
  EXPECT_EQ(scene.contacts[0].normal, (sim::Vec3{0, 0, 1}));
}

}  // namespace
}  // namespace dw::render
