// What the view shows (docs/design.md §9): a plain Scene, built by a free function from the Model, a
// State and the matched groups to highlight. The renderer draws a Scene and nothing else: it
// never touches the simulation.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "sim/bodies.h"
#include "sim/model.h"
#include "sim/state.h"

namespace dw::render {

// As in the physics (physics::ModuleShape): one module size (1) across; a cylinder stands upright,
// a disc lies across the x-z plane (axis y), a hexagonal prism stands upright.
enum class Shape { Box, Cylinder, Sphere, Disc, HexPrism };

struct Color {
  float r = 0, g = 0, b = 0;
  bool operator==(const Color&) const = default;
};

struct SceneModule {
  sim::ModuleId id = 0;
  sim::Pose pose;
  Color color;
  bool highlighted = false;  // a slot of a highlighted group
  bool selected = false;     // the module the user selected (the window): drawn solid and over
                             // whatever covers it, in a green ring (a group's module keeps its red rim
                             // inside the ring)
};

// A body that is not a module (a projectile, an obstacle).
struct SceneProp {
  Shape shape = Shape::Sphere;
  sim::Vec3 size{1, 1, 1};  // a box's extents; a sphere's diameter is size[0]
  sim::Pose pose;
};

// A matched group: the module filling each slot, in slot order. The view links slot 1 to slot 2
// to slot 3 ... and labels each module with its slot's name.
struct SceneGroup {
  std::string watch;
  int64_t t = 0;
  std::vector<std::string> slot_names;
  std::vector<sim::ModuleId> modules;
};

// A contact point the physics solver worked on in the step (sim::ContactPoint), in the world: where
// it lies on the first body, the normal pointing from the second body to the first, and the
// normal impulse the solver applied (N s). Who touches: as ContactPoint::a and b.
struct SceneContact {
  uint32_t a = 0, b = 0;
  sim::Vec3 point{}, normal{};
  float impulse = 0;
};

struct LegendEntry {
  Color color;
  std::string label;
};

struct Legend {
  std::string title;      // the variable; empty: no legend
  bool gradient = false;  // a continuous scale: entries are stops from the smallest value up
  std::vector<LegendEntry> entries;
};

struct Scene {
  std::string title;  // e.g. "leader_election  step 12"
  Shape module_shape = Shape::Box;
  std::vector<SceneModule> modules;  // the present ones, by id
  std::vector<SceneProp> props;
  std::vector<SceneGroup> groups;  // highlighted; the other modules are dimmed
  // The modules outside the groups dimmed even when no group shows: a player keeps one look while
  // matches come and go (the ensemble flickered between faded and vivid).
  bool fade_others = false;
  // Seeing inside a large ensemble (the window's Isolate and Cut): the modules outside the groups
  // left out, and those beyond a plane across one axis; the groups' and the selected module stay.
  bool isolate = false;
  struct Cut {
    int axis = 0;  // 0 x, 1 y, 2 z
    float at = 0;  // modules whose centre lies beyond this coordinate are left out
  };
  std::optional<Cut> cut;
  std::vector<SceneContact> contacts;  // drawn over the view when the scene settings ask for them
  Legend legend;
  float ground_z = -0.5f;
  std::optional<sim::Vec3> camera_eye, camera_target;  // unset: the camera is fitted
};

// Whether module m is drawn (and can be picked): isolate and the cut leave the others out.
inline bool shown(const Scene& scene, const SceneModule& m) {
  if (m.highlighted || m.selected) return true;
  if (scene.isolate) return false;
  return !scene.cut || m.pose.position[size_t(scene.cut->axis)] <= scene.cut->at;
}

// What a scene needs beyond the model and the state: how the world draws its bodies, and the
// view settings of the scenario (or the command line).
struct SceneSettings {
  std::string title;
  Shape module_shape = Shape::Box;
  std::vector<SceneProp> props;   // shapes and sizes; poses are taken from the state
  std::optional<float> ground_z;  // unset: half a module below the lowest lattice cell
  std::string color_by;           // a variable; empty: one colour for every module
  std::optional<sim::Vec3> camera_eye, camera_target;
  std::optional<sim::ModuleId> selected;  // the window's selected module
  bool contacts = false;                  // the physics' contact points and normals (Scene::contacts)
};

// Contact c's point in the world: on body a, whose frame is its cluster's (the world's for one
// latched to the ground), its own pose for a module in no cluster, a prop's pose, or the world's.
sim::Vec3 contact_point_in_world(const sim::Bodies& bodies, const sim::ContactPoint& c);

// Poses come from State::bodies in a physical world and from the lattice otherwise; colours from
// the `color_by` variable's values in the state (those of step state.step - 1). Groups naming a
// module that is absent or out of range are kept, but that slot is not drawn.
Scene build_scene(const sim::Model& model, const sim::State& state, std::span<const SceneGroup> groups,
                  const SceneSettings& settings);

}  // namespace dw::render
