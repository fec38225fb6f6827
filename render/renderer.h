// The 3D view (docs/design.md §9): draws a Scene with GL 3.3 core into whatever context is current,
// headless (OSMesa) or in a window. Modules are instanced meshes under simple lighting over a
// ground grid, coloured by a variable with a legend. When groups are highlighted, their modules
// stay solid and outlined while the others fade to translucent, so a group inside a cube shows
// through; the slots are linked in slot order and labelled. Edges are anti-aliased by a
// post-process (FXAA) and the flat layer by feathered edges of its own.
#pragma once

#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "render/camera.h"
#include "render/font.h"
#include "render/gl.h"
#include "render/image.h"
#include "render/overlay.h"
#include "render/scene.h"

namespace dw::render {

struct RenderError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// How finely a frame is drawn. Full is the picture `dwatch render` writes and the window shows
// when still. Moving is for frames that show only while the camera moves or play runs, and must
// come fast on a software rasteriser: no edge smoothing; the modules around a highlighted group
// opaque in their faded colours (not sorted, not blended; the group still shows through them);
// and a module of a lattice hidden on all six sides by its neighbours not drawn (through the gaps
// between modules it could show as a sliver). The still frame after is drawn Full again.
enum class RenderQuality { Full, Moving };

class Renderer {
 public:
  // Compiles the shaders and uploads the meshes in the context whose functions `gl` holds (which
  // must be current whenever the renderer is used). Throws RenderError.
  explicit Renderer(const Gl& gl, std::string font_path = DWATCH_FONT_FILE);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Draws the scene at width x height into framebuffer `target` (0: the context's default one),
  // which must be at least as large.
  void draw(const Scene& scene, int width, int height, unsigned target, RenderQuality quality = RenderQuality::Full);
  // Draws the scene and reads it back, top row first.
  Image render(const Scene& scene, int width, int height, RenderQuality quality = RenderQuality::Full);

  // The world-to-clip transform `draw` uses for this scene at this size (the camera placed in the
  // part of the image the title and legend leave): what picking needs.
  glm::mat4 view_projection(const Scene& scene, int width, int height);
  // The camera `draw` would fit to the scene at this size if the scene set none.
  Camera fitted_camera(const Scene& scene, int width, int height);
  // The camera `draw` uses for this scene at this size: the scene's, or fitted where it sets none
  // (a video keeps its first frame's for every frame, so that the view does not jump).
  Camera camera(const Scene& scene, int width, int height);

  // The largest image side the context takes.
  int max_size() const { return max_size_; }
  // The least text size (pixels) of the title, legend and labels drawn from now on (text_size).
  void set_least_text_size(int pixels) { least_text_ = pixels; }

 private:
  struct Program;
  struct Mesh;
  struct Instance;
  struct FontTexture;

  void resize(int width, int height);
  void draw_bodies(const Scene& scene, const Camera& camera, const glm::mat4& view_projection, RenderQuality quality);
  // The selected module and a ring around it, over everything drawn before.
  void draw_selection(const Scene& scene);
  void smooth_edges(const Scene& scene, const glm::mat4& view_projection);
  FontTexture& font(int pixel_height);
  void draw_instances(const Mesh& mesh, const std::vector<Instance>& instances);
  void draw_ground(const Scene& scene, const glm::mat4& view_projection);
  void draw_overlay(const std::vector<OverlayVertex>& vertices, const FontTexture& font, int width, int height);

  const Gl& gl_;
  std::string font_path_;
  std::unique_ptr<Program> mesh_program_, ground_program_, overlay_program_, fxaa_program_;
  std::map<Shape, std::unique_ptr<Mesh>> meshes_;
  std::map<int, std::unique_ptr<FontTexture>> fonts_;
  unsigned instance_buffer_ = 0, quad_vao_ = 0, quad_buffer_ = 0, overlay_vao_ = 0, overlay_buffer_ = 0, empty_vao_ = 0;
  // The bodies are drawn into a texture, which the edge smoothing reads; `render` draws the
  // finished picture into the output framebuffer and reads it back.
  unsigned scene_fbo_ = 0, scene_color_ = 0, scene_depth_ = 0, output_fbo_ = 0, output_color_ = 0;
  int width_ = 0, height_ = 0, max_size_ = 0;
  int least_text_ = 12;  // text_size's least
};

}  // namespace dw::render
