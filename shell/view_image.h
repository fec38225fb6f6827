// The headless 3D view of a scenario (docs/design.md §9), shared by `dwatch render` and
// `dwatch run --render`: a Scene from the run's state and matches, drawn through OSMesa to PNG.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "render/image.h"
#include "render/scene.h"
#include "scenarios/scenario.h"
#include "sim/output_file.h"
#include "sim/session.h"

namespace dw::shell {

enum class Highlight { First, All, None };

// How the scenario's world draws (module shape, props, ground) and its view settings; a
// non-empty `color_by` wins over the scenario's.
render::SceneSettings scene_settings(const scenarios::Scenario& scenario, const std::string& color_by);

// The matched groups of step t in the session's match lists, by watch in scenario order: the first
// one, all, or none.
std::vector<render::SceneGroup> groups_at(const sim::Session& session, int64_t t, Highlight highlight);

// Checks a --color-by variable against the model; the error names the variables there are.
std::string check_color_by(const sim::Model& model, const std::string& color_by);

// A camera the user gave that draws none of the ensemble (render::camera_misses) is refused: its
// message printed, true returned (exit 2), rather than a picture of nothing written.
bool camera_refused(const render::Scene& scene, int width, int height);

// Draws the scene headless (OSMesa): the picture, or why not (a camera that misses the ensemble).
std::variant<render::Image, std::string> render_view(const render::Scene& scene, int width, int height);

// Draws the scene headless and writes it as a PNG to `out`, for the caller to commit (or not, when
// it was stopped meanwhile); an error message, or empty.
std::string write_view(const render::Scene& scene, sim::OutputFile& out, int width, int height);

}  // namespace dw::shell
