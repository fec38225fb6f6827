// A scenario's [physics] (docs/design.md §8): the Bullet world's settings and its [[physics.prop]]
// bodies; nothing when it is off (a static lattice).
#include <array>
#include <cmath>

#include "scenarios/scenario_loader.h"

namespace dw::scenarios {

namespace {

std::optional<physics::ModuleShape> module_shape(TableReader& r, std::string_view key) {
  const auto name = r.string(key);
  if (!name) return std::nullopt;
  if (*name == "box") return physics::ModuleShape::Box;
  if (*name == "cylinder") return physics::ModuleShape::Cylinder;
  if (*name == "sphere") return physics::ModuleShape::Sphere;
  if (*name == "disc") return physics::ModuleShape::Disc;
  if (*name == "hex_prism") return physics::ModuleShape::HexPrism;
  r.error(key, "'" + std::string(key) +
                   "' must be \"box\", \"cylinder\", \"sphere\", \"disc\" or \"hex_prism\", not \"" + *name + "\"");
  return std::nullopt;
}

sim::Vec3 vec3(const std::optional<std::vector<double>>& v, sim::Vec3 otherwise) {
  return v ? sim::Vec3{float((*v)[0]), float((*v)[1]), float((*v)[2])} : otherwise;
}

// A unit quaternion [x, y, z, w] from the four numbers given, scaled to length 1 (a turn written
// to a few digits, as [0.7071, 0, 0, 0.7071], is the turn meant); all four zero is no turn at all.
std::array<float, 4> orientation(TableReader& r, const std::vector<double>& q) {
  const double length = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (length < 1e-6) {
    r.error("orientation", "'orientation' is a turn as a quaternion [x, y, z, w], not all zero");
    return {0, 0, 0, 1};
  }
  return {float(q[0] / length), float(q[1] / length), float(q[2] / length), float(q[3] / length)};
}

}  // namespace

// [physics]: nothing when it is off (a static lattice).
std::optional<physics::PhysicsSettings> Loader::physics_settings(TableReader& root) {
  const toml::table* t = root.table("physics");
  if (!t) return std::nullopt;
  TableReader r(*t, diagnostics, "[physics]");
  physics::PhysicsSettings p;
  const bool on = r.boolean("enabled").value_or(false);
  p.dt = float(r.number("dt", 1e-4, 1).value_or(p.dt));
  p.gravity = vec3(r.numbers("gravity", 3, -1000, 1000), p.gravity);  // m/s^2: 100 g either way
  p.shape = module_shape(r, "shape");
  p.module_mass = float(r.number("module_mass", 1e-3, 1e6).value_or(p.module_mass));
  p.contact_threshold = float(
      r.number("contact_threshold", 0, physics::PhysicsSettings::kMaxContactThreshold).value_or(p.contact_threshold));
  p.bonds = r.boolean("bonds").value_or(p.bonds);
  p.anchor = r.boolean("anchor").value_or(p.anchor);
  p.break_force = float(r.number("break_force", 0, 1e12).value_or(p.break_force));
  p.friction = float(r.number("friction", 0, 10).value_or(p.friction));
  p.restitution = float(r.number("restitution", 0, 1).value_or(p.restitution));
  // A lever in metres, at most a module's radius (0.5): beyond it no rolling body would roll.
  p.rolling_friction = float(r.number("rolling_friction", 0, 0.5).value_or(p.rolling_friction));
  p.spinning_friction = float(r.number("spinning_friction", 0, 0.5).value_or(p.spinning_friction));
  p.solver_iterations = int(r.integer("solver_iterations", 1, 1000).value_or(p.solver_iterations));
  p.substeps = int(r.integer("substeps", 1, 100).value_or(p.substeps));
  p.substep_travel = float(r.number("substep_travel", 1e-4, 100).value_or(p.substep_travel));
  p.max_substeps = int(r.integer("max_substeps", 1, 100).value_or(std::max(p.max_substeps, p.substeps)));
  if (p.max_substeps < p.substeps) r.error("max_substeps", "is below substeps (" + std::to_string(p.substeps) + ")");
  p.sleep_after = float(r.number("sleep_after", 0, 1e6).value_or(p.sleep_after));
  p.move_steps = r.integer("move_steps", 1, 100'000).value_or(p.move_steps);
  for (const toml::table* prop : r.tables("prop")) {
    TableReader q(*prop, diagnostics, "[[physics.prop]]");
    physics::PropSpec b;
    b.shape = module_shape(q, "shape").value_or(b.shape);
    if (b.shape != physics::ModuleShape::Box && b.shape != physics::ModuleShape::Sphere)
      q.error("shape", "a prop is a \"box\" or a \"sphere\"");
    b.size = vec3(q.numbers("size", 3, 1e-3, 1e3), b.size);
    if (q.has("diameter")) b.size[0] = float(q.number("diameter", 1e-3, 1e3).value_or(1));
    b.mass = float(q.number("mass", 0, 1e9).value_or(b.mass));
    b.pose.position = vec3(q.numbers("position", 3, -kMaxCoordinate, kMaxCoordinate), b.pose.position);
    b.velocity.linear = vec3(q.numbers("velocity", 3, -1e4, 1e4), b.velocity.linear);            // m/s
    b.velocity.angular = vec3(q.numbers("angular_velocity", 3, -1e4, 1e4), b.velocity.angular);  // rad/s
    if (const auto turn = q.numbers("orientation", 4, -1, 1)) b.pose.orientation = orientation(q, *turn);
    if (!q.has("position")) q.missing("position");
    q.finish();
    p.props.push_back(b);
  }
  r.finish();
  if (!on) return std::nullopt;
  return p;
}

}  // namespace dw::scenarios
