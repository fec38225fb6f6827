// A scenario's [view]: the variable that colours the modules and the camera, and the check of a
// camera a user gives (in the file, or on the command line).
#include <algorithm>
#include <array>
#include <cmath>

#include "scenarios/scenario_loader.h"

namespace dw::scenarios {

// [view]: color_by, camera_eye, camera_target; the camera checked when both are given.
void Loader::view(TableReader& root, ViewSettings& out) {
  const toml::table* t = root.table("view");
  if (!t) return;
  TableReader r(*t, diagnostics, "[view]");
  out.color_by = r.string("color_by").value_or("");
  if (auto eye = r.numbers("camera_eye", 3, -kMaxCoordinate, kMaxCoordinate))
    out.camera_eye = std::array<double, 3>{(*eye)[0], (*eye)[1], (*eye)[2]};
  if (auto target = r.numbers("camera_target", 3, -kMaxCoordinate, kMaxCoordinate))
    out.camera_target = std::array<double, 3>{(*target)[0], (*target)[1], (*target)[2]};
  if (out.camera_eye && out.camera_target)
    if (std::string problem = camera_problem(*out.camera_eye, *out.camera_target); !problem.empty())
      r.error("camera_target", problem);
  r.finish();
}

// Once the programs are known: `color_by` names a variable one of them has. False, with the
// error at the key, when none has it.
bool Loader::check_color_by(const ViewSettings& view, const sim::Model& model, const toml::table& doc) {
  if (view.color_by.empty() || model.column(view.color_by) >= 0) return true;
  TableReader r(*doc.get("view")->as_table(), diagnostics, "[view]");
  r.error("color_by", "no program has a variable named \"" + view.color_by + "\"");
  return false;
}

std::string camera_problem(std::span<const double> eye, std::span<const double> target) {
  for (std::span<const double> v : {eye, target})
    for (double c : v)
      if (!std::isfinite(c) || std::abs(c) > kMaxCoordinate)
        return "a camera coordinate must be a finite number from -1e6 to 1e6, not " + std::to_string(c);
  // On its target, or so near that no direction can be told (the renderer would draw the fitted
  // view instead, render::make_camera): a millionth of the eye's distance from the origin.
  if (eye.size() == 3 && target.size() == 3 &&
      std::hypot(eye[0] - target[0], eye[1] - target[1], eye[2] - target[2]) <=
          1e-6 * std::max(1.0, std::hypot(eye[0], eye[1], eye[2])))
    return "the camera's eye is on its target, so it looks nowhere: move one of them";
  return "";
}

}  // namespace dw::scenarios
