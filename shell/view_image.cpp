#include "shell/view_image.h"

#include <iostream>

#include "physics/bullet_world.h"
#include "render/camera.h"
#include "render/image.h"
#include "render/osmesa_context.h"
#include "render/renderer.h"

namespace dw::shell {
namespace {

render::Shape shape_of(physics::ModuleShape s) {
  switch (s) {
    case physics::ModuleShape::Box: return render::Shape::Box;
    case physics::ModuleShape::Cylinder: return render::Shape::Cylinder;
    case physics::ModuleShape::Sphere: return render::Shape::Sphere;
    case physics::ModuleShape::Disc: return render::Shape::Disc;
    case physics::ModuleShape::HexPrism: return render::Shape::HexPrism;
  }
  return render::Shape::Box;
}

}  // namespace

render::SceneSettings scene_settings(const scenarios::Scenario& scenario, const std::string& color_by) {
  render::SceneSettings s;
  s.title = scenario.name;
  s.module_shape = shape_of(physics::default_shape(scenario.model->lattice.spec.kind));
  s.color_by = color_by.empty() ? scenario.view.color_by : color_by;
  auto vec = [](const std::array<double, 3>& a) { return sim::Vec3{float(a[0]), float(a[1]), float(a[2])}; };
  if (scenario.view.camera_eye) s.camera_eye = vec(*scenario.view.camera_eye);
  if (scenario.view.camera_target) s.camera_target = vec(*scenario.view.camera_target);
  if (const auto* world = dynamic_cast<const physics::BulletWorld*>(scenario.world.get())) {
    s.module_shape = shape_of(world->shape());
    s.ground_z = world->ground_z();
    for (const physics::PropSpec& p : world->settings().props) s.props.push_back({shape_of(p.shape), p.size, p.pose});
  }
  return s;
}

std::vector<render::SceneGroup> groups_at(const sim::Session& session, int64_t t, Highlight highlight) {
  std::vector<render::SceneGroup> groups;
  if (highlight == Highlight::None) return groups;
  for (uint32_t w = 0; w < session.watches().size(); ++w) {
    const watch::Watchpoint& wp = session.watches()[w].hosted.watchpoint;
    const size_t k = size_t(wp.program.slot_count());
    if (k == 0) continue;  // a zero-slot match (docs/design.md §4c) has no module to light
    const sim::MatchList& list = session.matches(w);
    for (auto [i, last] = list.at(t); i < last; ++i) {
      groups.push_back(
          {wp.name, t, wp.program.slot_names, {list.slots.begin() + i * k, list.slots.begin() + (i + 1) * k}});
      if (highlight == Highlight::First) return groups;
    }
  }
  return groups;
}

std::string check_color_by(const sim::Model& model, const std::string& color_by) {
  if (color_by.empty() || model.column(color_by) >= 0) return {};
  std::string names;
  for (const std::string& v : model.universe.variables) names += (names.empty() ? "" : ", ") + v;
  return "--color-by: no program has a variable named \"" + color_by + "\" (there are: " + names + ")";
}

bool camera_refused(const render::Scene& scene, int width, int height) {
  const std::string why = render::camera_misses(scene, width, height);
  if (!why.empty()) std::cerr << "dwatch: error: " << why << "\n";
  return !why.empty();
}

std::variant<render::Image, std::string> render_view(const render::Scene& scene, int width, int height) {
  if (std::string why = render::camera_misses(scene, width, height); !why.empty()) return why;
  auto context = render::OsMesaContext::create();
  if (auto* error = std::get_if<std::string>(&context)) return *error;
  try {
    render::Renderer renderer(std::get<0>(context)->gl());
    return renderer.render(scene, width, height);
  } catch (const render::RenderError& e) {
    return std::string(e.what());
  }
}

std::string write_view(const render::Scene& scene, sim::OutputFile& out, int width, int height) {
  auto image = render_view(scene, width, height);
  if (auto* error = std::get_if<std::string>(&image)) return *error;
  std::string error;
  const auto bytes = render::encode_png(std::get<render::Image>(image), &error);
  if (!bytes) return error;
  out.stream().write(reinterpret_cast<const char*>(bytes->data()), static_cast<std::streamsize>(bytes->size()));
  return {};
}

}  // namespace dw::shell
