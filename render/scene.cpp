#include "render/scene.h"

#include <algorithm>
#include <glm/gtc/quaternion.hpp>
#include <limits>

#include "render/palette.h"

namespace dw::render {

Scene build_scene(const sim::Model& model, const sim::State& state, std::span<const SceneGroup> groups,
                  const SceneSettings& settings) {
  Scene scene;
  scene.title = settings.title;
  scene.module_shape = settings.module_shape;
  scene.camera_eye = settings.camera_eye;
  scene.camera_target = settings.camera_target;

  const uint32_t n = model.module_count();
  const bool physical = state.bodies.poses.size() == n;
  auto present = [&](sim::ModuleId m) { return m < n && (state.present.size() != n || state.present[m]); };

  float lowest = std::numeric_limits<float>::max();
  for (sim::ModuleId m = 0; m < n; ++m) lowest = std::min(lowest, model.lattice.position(m)[2]);
  scene.ground_z = settings.ground_z.value_or(n == 0 ? -0.5f : lowest - 0.5f);

  // Colours: the variable's values over the present modules fix the scale.
  const int column = settings.color_by.empty() ? -1 : model.column(settings.color_by);
  const size_t vars = model.variable_count();
  const bool has_values = state.values.size() == size_t(n) * vars;
  auto value = [&](sim::ModuleId m) {
    return has_values ? state.values[size_t(m) * vars + size_t(column)] : model.initial_values[size_t(column)];
  };
  std::vector<int64_t> values;
  if (column >= 0) {
    for (sim::ModuleId m = 0; m < n; ++m)
      if (present(m)) values.push_back(value(m));
  }
  const ColorScale scale(settings.color_by, values);
  if (column >= 0) scene.legend = scale.legend();

  std::vector<uint8_t> highlighted(n, 0);
  for (const SceneGroup& g : groups)
    for (sim::ModuleId m : g.modules)
      if (m < n) highlighted[m] = 1;

  for (sim::ModuleId m = 0; m < n; ++m) {
    if (!present(m)) continue;
    SceneModule sm;
    sm.id = m;
    if (physical) {
      sm.pose = state.bodies.poses[m];
    } else {
      sm.pose.position = model.lattice.position(m);
    }
    sm.color = column >= 0 ? scale.color(value(m)) : kNeutralModule;
    sm.highlighted = highlighted[m] != 0;
    sm.selected = settings.selected == m;
    scene.modules.push_back(sm);
  }

  scene.props = settings.props;
  for (size_t i = 0; i < scene.props.size() && i < state.bodies.prop_poses.size(); ++i)
    scene.props[i].pose = state.bodies.prop_poses[i];

  scene.groups.assign(groups.begin(), groups.end());
  if (settings.contacts)
    for (const sim::ContactPoint& c : state.bodies.contacts)
      scene.contacts.push_back({c.a, c.b, contact_point_in_world(state.bodies, c), c.normal, c.impulse});
  return scene;
}

sim::Vec3 contact_point_in_world(const sim::Bodies& bodies, const sim::ContactPoint& c) {
  sim::Pose frame;  // the world's: the ground's
  if (c.a < bodies.poses.size()) {
    const uint32_t cluster = bodies.cluster_of.empty() ? sim::kNoCluster : bodies.cluster_of[c.a];
    if (cluster == sim::kNoCluster) frame = bodies.poses[c.a];
    else if (!bodies.clusters[cluster].anchored) frame = bodies.clusters[cluster].pose;
  } else if (c.a != sim::kGroundContact && sim::contact_prop(0) - c.a < bodies.prop_poses.size()) {
    frame = bodies.prop_poses[sim::contact_prop(0) - c.a];
  }
  const auto& q = frame.orientation;
  const glm::vec3 local(c.local_a[0], c.local_a[1], c.local_a[2]);
  const glm::vec3 turned = glm::quat(q[3], q[0], q[1], q[2]) * local;  // glm's quat is (w, x, y, z)
  return {frame.position[0] + turned.x, frame.position[1] + turned.y, frame.position[2] + turned.z};
}

}  // namespace dw::render
