#include "render/renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <optional>
#include <unordered_set>

#include "render/annotations.h"
#include "render/meshes.h"
#include "render/overlay.h"
#include "render/shaders.h"

namespace dw::render {
namespace {

constexpr glm::vec3 kBackground{0.965f, 0.969f, 0.976f};
constexpr glm::vec3 kGround{0.905f, 0.914f, 0.929f};
constexpr glm::vec3 kGridLine{0.78f, 0.80f, 0.83f};
constexpr glm::vec4 kOutline{0.84f, 0.11f, 0.16f, 1};  // as the slot links
// The selected module's ring: a green no colour scale uses, apart from the group's red.
constexpr glm::vec4 kSelectedOutline{0.10f, 0.78f, 0.22f, 1};
// How far the selection's ring reaches past the selected module, in module sizes: wider than the
// group's rim, so that a selected module of the group shows both (red inside, green outside).
constexpr float kSelectionScale = 1.34f;
constexpr Color kPropColor{0.50f, 0.46f, 0.43f};
// Modules are drawn a little smaller than their cell, so that each one shows in a lattice.
constexpr float kModuleScale = 0.9f;
// How far the outline reaches past a highlighted module, in module sizes.
constexpr float kOutlineScale = 1.12f;

glm::mat4 transform(const sim::Pose& pose, glm::vec3 scale) {
  const auto& p = pose.position;
  const auto& q = pose.orientation;  // x, y, z, w
  return glm::translate(glm::mat4(1), glm::vec3(p[0], p[1], p[2])) * glm::mat4_cast(glm::quat(q[3], q[0], q[1], q[2])) *
         glm::scale(glm::mat4(1), scale);
}

// Per module: whether it sits on the unit lattice, upright, with a module on each of its six sides
// in the same way, so that from outside it shows at most as slivers through the gaps between
// modules (what a moving frame may leave out).
std::vector<bool> enclosed_modules(const Scene& scene) {
  std::vector<bool> enclosed(scene.modules.size(), false);
  auto cell_of = [](const sim::Pose& pose) -> std::optional<std::array<int32_t, 3>> {
    const auto& q = pose.orientation;
    if (q[0] != 0 || q[1] != 0 || q[2] != 0) return std::nullopt;
    std::array<int32_t, 3> cell{};
    for (int d = 0; d < 3; ++d) {
      const float p = pose.position[size_t(d)];
      if (!(std::abs(p) < 1e6f) || p != std::nearbyint(p)) return std::nullopt;
      cell[size_t(d)] = int32_t(p);
    }
    return cell;
  };
  // 21 bits a coordinate: lattices are far smaller.
  auto key = [](const std::array<int32_t, 3>& c) {
    return (uint64_t(uint32_t(c[0]) & 0x1fffff) << 42) | (uint64_t(uint32_t(c[1]) & 0x1fffff) << 21) |
           uint64_t(uint32_t(c[2]) & 0x1fffff);
  };
  std::unordered_set<uint64_t> occupied;
  occupied.reserve(scene.modules.size());
  std::vector<std::optional<std::array<int32_t, 3>>> cells;
  cells.reserve(scene.modules.size());
  for (const SceneModule& m : scene.modules) {
    cells.push_back(cell_of(m.pose));
    // Only what is drawn encloses: a cut opens the modules behind its face.
    if (cells.back() && shown(scene, m)) occupied.insert(key(*cells.back()));
  }
  for (size_t i = 0; i < cells.size(); ++i) {
    if (!cells[i]) continue;
    bool all = true;
    for (int d = 0; d < 3 && all; ++d)
      for (int side : {-1, 1}) {
        std::array<int32_t, 3> next = *cells[i];
        next[size_t(d)] += side;
        if (!occupied.count(key(next))) {
          all = false;
          break;
        }
      }
    enclosed[i] = all;
  }
  return enclosed;
}

// A colour faded towards a pale grey: the modules around a highlighted group.
glm::vec4 dimmed(Color c) {
  const float grey = 0.3f * c.r + 0.59f * c.g + 0.11f * c.b;
  const glm::vec3 muted = glm::mix(glm::vec3(c.r, c.g, c.b), glm::vec3(grey), 0.4f);
  return glm::vec4(glm::mix(muted, glm::vec3(0.92f), 0.3f), 0.32f);
}

}  // namespace

struct Renderer::Program {
  const Gl& gl;
  GLuint id = 0;
  Program(const Gl& g, std::string_view vertex, std::string_view fragment, const char* name) : gl(g) {
    const GLuint vs = compile(GL_VERTEX_SHADER, vertex, name);
    GLuint fs = 0;
    try {
      fs = compile(GL_FRAGMENT_SHADER, fragment, name);
    } catch (const RenderError&) {
      gl.DeleteShader(vs);
      throw;
    }
    id = gl.CreateProgram();
    gl.AttachShader(id, vs);
    gl.AttachShader(id, fs);
    gl.LinkProgram(id);
    gl.DeleteShader(vs);
    gl.DeleteShader(fs);
    GLint ok = 0;
    gl.GetProgramiv(id, GL_LINK_STATUS, &ok);
    if (!ok) {
      char log[2048] = {};
      gl.GetProgramInfoLog(id, sizeof log, nullptr, log);
      gl.DeleteProgram(id);
      throw RenderError(std::string("the ") + name + " shaders do not link: " + log);
    }
  }
  ~Program() { gl.DeleteProgram(id); }
  GLuint compile(GLenum kind, std::string_view source, const char* name) {
    const GLuint s = gl.CreateShader(kind);
    const char* text = source.data();
    const GLint length = GLint(source.size());
    gl.ShaderSource(s, 1, &text, &length);
    gl.CompileShader(s);
    GLint ok = 0;
    gl.GetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      char log[2048] = {};
      gl.GetShaderInfoLog(s, sizeof log, nullptr, log);
      gl.DeleteShader(s);
      throw RenderError(std::string("the ") + name + " shader does not compile: " + log);
    }
    return s;
  }
  GLint at(const char* uniform) const { return gl.GetUniformLocation(id, uniform); }
};

// An indexed mesh (make_indexed_mesh): its vertex array holds the vertices, the indices and the
// instance attributes.
struct Renderer::Mesh {
  GLuint vao = 0, vertices = 0, indices = 0;
  GLsizei count = 0;  // indices
};

// Per instance: where the mesh goes and its colour (alpha < 1: translucent).
struct Renderer::Instance {
  glm::mat4 model;
  glm::vec4 color;
};

struct Renderer::FontTexture {
  FontAtlas atlas;
  GLuint texture = 0;
};

Renderer::Renderer(const Gl& gl, std::string font_path) : gl_(gl), font_path_(std::move(font_path)) {
  mesh_program_ = std::make_unique<Program>(gl_, shaders::mesh_vert, shaders::mesh_frag, "mesh");
  ground_program_ = std::make_unique<Program>(gl_, shaders::ground_vert, shaders::ground_frag, "ground");
  overlay_program_ = std::make_unique<Program>(gl_, shaders::overlay_vert, shaders::overlay_frag, "overlay");
  fxaa_program_ = std::make_unique<Program>(gl_, shaders::fxaa_vert, shaders::fxaa_frag, "fxaa");
  GLint renderbuffer = 0, texture = 0;
  gl_.GetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &renderbuffer);
  gl_.GetIntegerv(GL_MAX_TEXTURE_SIZE, &texture);
  max_size_ = std::min(renderbuffer, texture);

  gl_.GenBuffers(1, &instance_buffer_);
  for (Shape shape : {Shape::Box, Shape::Cylinder, Shape::Sphere, Shape::Disc, Shape::HexPrism}) {
    const IndexedMesh shape_mesh = make_indexed_mesh(shape);
    const std::vector<MeshVertex>& vertices = shape_mesh.vertices;
    auto mesh = std::make_unique<Mesh>();
    mesh->count = GLsizei(shape_mesh.indices.size());
    gl_.GenVertexArrays(1, &mesh->vao);
    gl_.BindVertexArray(mesh->vao);
    gl_.GenBuffers(1, &mesh->vertices);
    gl_.BindBuffer(GL_ARRAY_BUFFER, mesh->vertices);
    gl_.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(MeshVertex)), vertices.data(), GL_STATIC_DRAW);
    gl_.GenBuffers(1, &mesh->indices);  // the element buffer binding is part of the vertex array
    gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, mesh->indices);
    gl_.BufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(shape_mesh.indices.size() * sizeof(uint32_t)),
                   shape_mesh.indices.data(), GL_STATIC_DRAW);
    gl_.EnableVertexAttribArray(0);
    gl_.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(MeshVertex),
                            reinterpret_cast<void*>(offsetof(MeshVertex, position)));
    gl_.EnableVertexAttribArray(1);
    gl_.VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(MeshVertex),
                            reinterpret_cast<void*>(offsetof(MeshVertex, normal)));
    // The instance attributes read the shared instance buffer: a mat4 as four columns, a colour.
    gl_.BindBuffer(GL_ARRAY_BUFFER, instance_buffer_);
    for (GLuint c = 0; c < 4; ++c) {
      gl_.EnableVertexAttribArray(2 + c);
      gl_.VertexAttribPointer(2 + c, 4, GL_FLOAT, GL_FALSE, sizeof(Instance),
                              reinterpret_cast<void*>(offsetof(Instance, model) + c * sizeof(glm::vec4)));
      gl_.VertexAttribDivisor(2 + c, 1);
    }
    gl_.EnableVertexAttribArray(6);
    gl_.VertexAttribPointer(6, 4, GL_FLOAT, GL_FALSE, sizeof(Instance),
                            reinterpret_cast<void*>(offsetof(Instance, color)));
    gl_.VertexAttribDivisor(6, 1);
    meshes_[shape] = std::move(mesh);
  }

  const float corners[] = {-1, -1, 1, -1, 1, 1, -1, -1, 1, 1, -1, 1};
  gl_.GenVertexArrays(1, &quad_vao_);
  gl_.BindVertexArray(quad_vao_);
  gl_.GenBuffers(1, &quad_buffer_);
  gl_.BindBuffer(GL_ARRAY_BUFFER, quad_buffer_);
  gl_.BufferData(GL_ARRAY_BUFFER, sizeof corners, corners, GL_STATIC_DRAW);
  gl_.EnableVertexAttribArray(0);
  gl_.VertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 2 * sizeof(float), nullptr);

  gl_.GenVertexArrays(1, &overlay_vao_);
  gl_.BindVertexArray(overlay_vao_);
  gl_.GenBuffers(1, &overlay_buffer_);
  gl_.BindBuffer(GL_ARRAY_BUFFER, overlay_buffer_);
  gl_.EnableVertexAttribArray(0);
  gl_.VertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, sizeof(OverlayVertex),
                          reinterpret_cast<void*>(offsetof(OverlayVertex, x)));
  gl_.EnableVertexAttribArray(1);
  gl_.VertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, sizeof(OverlayVertex),
                          reinterpret_cast<void*>(offsetof(OverlayVertex, u)));
  gl_.EnableVertexAttribArray(2);
  gl_.VertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, sizeof(OverlayVertex),
                          reinterpret_cast<void*>(offsetof(OverlayVertex, r)));
  gl_.GenVertexArrays(1, &empty_vao_);  // the core profile draws nothing without a vertex array
  gl_.BindVertexArray(0);
}

Renderer::~Renderer() {
  for (auto& [shape, mesh] : meshes_) {
    gl_.DeleteVertexArrays(1, &mesh->vao);
    gl_.DeleteBuffers(1, &mesh->vertices);
    gl_.DeleteBuffers(1, &mesh->indices);
  }
  for (auto& [size, font] : fonts_) gl_.DeleteTextures(1, &font->texture);
  const GLuint vaos[] = {quad_vao_, overlay_vao_, empty_vao_};
  gl_.DeleteVertexArrays(3, vaos);
  const GLuint buffers[] = {instance_buffer_, quad_buffer_, overlay_buffer_};
  gl_.DeleteBuffers(3, buffers);
  const GLuint fbos[] = {scene_fbo_, output_fbo_};
  gl_.DeleteFramebuffers(2, fbos);
  gl_.DeleteTextures(1, &scene_color_);
  const GLuint rbs[] = {scene_depth_, output_color_};
  gl_.DeleteRenderbuffers(2, rbs);
}

void Renderer::resize(int width, int height) {
  if (width == width_ && height == height_) return;
  if (width < 1 || height < 1 || width > max_size_ || height > max_size_)
    throw RenderError("an image of " + std::to_string(width) + "x" + std::to_string(height) +
                      " is out of range (1 to " + std::to_string(max_size_) + " per side)");
  if (!scene_fbo_) {
    gl_.GenFramebuffers(1, &scene_fbo_);
    gl_.GenFramebuffers(1, &output_fbo_);
    gl_.GenTextures(1, &scene_color_);
    gl_.GenRenderbuffers(1, &scene_depth_);
    gl_.GenRenderbuffers(1, &output_color_);
  }
  gl_.BindTexture(GL_TEXTURE_2D, scene_color_);
  gl_.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);  // the smoothing samples between pixels
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  gl_.BindRenderbuffer(GL_RENDERBUFFER, scene_depth_);
  gl_.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, width, height);
  gl_.BindFramebuffer(GL_FRAMEBUFFER, scene_fbo_);
  gl_.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, scene_color_, 0);
  gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, scene_depth_);
  if (gl_.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw RenderError("the scene framebuffer is incomplete");
  gl_.BindRenderbuffer(GL_RENDERBUFFER, output_color_);
  gl_.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  gl_.BindFramebuffer(GL_FRAMEBUFFER, output_fbo_);
  gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, output_color_);
  if (gl_.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw RenderError("the output framebuffer is incomplete");
  gl_.BindFramebuffer(GL_FRAMEBUFFER, 0);
  width_ = width;
  height_ = height;
}

Renderer::FontTexture& Renderer::font(int pixel_height) {
  auto& slot = fonts_[pixel_height];
  if (slot) return *slot;
  auto baked = FontAtlas::bake(font_path_, float(pixel_height));
  if (auto* error = std::get_if<std::string>(&baked)) {
    fonts_.erase(pixel_height);
    throw RenderError(*error);
  }
  auto f = std::make_unique<FontTexture>(FontTexture{std::get<FontAtlas>(std::move(baked)), 0});
  gl_.GenTextures(1, &f->texture);
  gl_.BindTexture(GL_TEXTURE_2D, f->texture);
  gl_.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  gl_.TexImage2D(GL_TEXTURE_2D, 0, GL_R8, f->atlas.width(), f->atlas.height(), 0, GL_RED, GL_UNSIGNED_BYTE,
                 f->atlas.pixels().data());
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  slot = std::move(f);
  return *slot;
}

void Renderer::draw_instances(const Mesh& mesh, const std::vector<Instance>& instances) {
  if (instances.empty()) return;
  gl_.BindBuffer(GL_ARRAY_BUFFER, instance_buffer_);
  gl_.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(instances.size() * sizeof(Instance)), instances.data(), GL_STREAM_DRAW);
  gl_.BindVertexArray(mesh.vao);
  gl_.DrawElementsInstanced(GL_TRIANGLES, mesh.count, GL_UNSIGNED_INT, nullptr, GLsizei(instances.size()));
}

void Renderer::draw_ground(const Scene& scene, const glm::mat4& view_projection) {
  const Bounds b = scene_bounds(scene);
  const float reach = b.radius() * 2.5f + 3;
  const Program& p = *ground_program_;
  gl_.UseProgram(p.id);
  gl_.UniformMatrix4fv(p.at("u_view_projection"), 1, GL_FALSE, glm::value_ptr(view_projection));
  gl_.Uniform2f(p.at("u_center"), b.center().x, b.center().y);
  gl_.Uniform1f(p.at("u_half_size"), reach);
  gl_.Uniform1f(p.at("u_fade_radius"), reach);
  gl_.Uniform1f(p.at("u_z"), scene.ground_z);
  gl_.Uniform3fv(p.at("u_ground"), 1, glm::value_ptr(kGround));
  gl_.Uniform3fv(p.at("u_line"), 1, glm::value_ptr(kGridLine));
  gl_.Uniform3fv(p.at("u_background"), 1, glm::value_ptr(kBackground));
  gl_.BindVertexArray(quad_vao_);
  gl_.DrawArrays(GL_TRIANGLES, 0, 6);
}

void Renderer::draw_overlay(const std::vector<OverlayVertex>& vertices, const FontTexture& font, int width,
                            int height) {
  const Program& p = *overlay_program_;
  gl_.UseProgram(p.id);
  gl_.Uniform2f(p.at("u_size"), float(width), float(height));
  gl_.Uniform1i(p.at("u_atlas"), 0);
  gl_.ActiveTexture(GL_TEXTURE0);
  gl_.BindTexture(GL_TEXTURE_2D, font.texture);
  gl_.BindVertexArray(overlay_vao_);
  gl_.BindBuffer(GL_ARRAY_BUFFER, overlay_buffer_);
  gl_.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(OverlayVertex)), vertices.data(), GL_STREAM_DRAW);
  gl_.DrawArrays(GL_TRIANGLES, 0, GLsizei(vertices.size()));
}

glm::mat4 Renderer::view_projection(const Scene& scene, int width, int height) {
  const Region region = view_region(scene, font(text_size(height, least_text_)).atlas, width, height);
  return render::view_projection(make_camera(scene, width, height, region), width, height, region);
}

Camera Renderer::fitted_camera(const Scene& scene, int width, int height) {
  Scene unset = scene;
  unset.camera_eye.reset();
  unset.camera_target.reset();
  return make_camera(unset, width, height,
                     view_region(unset, font(text_size(height, least_text_)).atlas, width, height));
}

Camera Renderer::camera(const Scene& scene, int width, int height) {
  return make_camera(scene, width, height,
                     view_region(scene, font(text_size(height, least_text_)).atlas, width, height));
}

void Renderer::draw(const Scene& scene, int width, int height, unsigned target, RenderQuality quality) {
  resize(width, height);
  FontTexture& text = font(text_size(height, least_text_));
  const Region region = view_region(scene, text.atlas, width, height);
  const Camera camera = make_camera(scene, width, height, region);
  const glm::mat4 view_projection = render::view_projection(camera, width, height, region);

  gl_.BindFramebuffer(GL_FRAMEBUFFER, scene_fbo_);
  gl_.Viewport(0, 0, width, height);
  draw_bodies(scene, camera, view_projection, quality);
  draw_selection(scene);
  gl_.Disable(GL_DEPTH_TEST);
  gl_.Disable(GL_CULL_FACE);
  gl_.Disable(GL_BLEND);

  gl_.BindFramebuffer(GL_READ_FRAMEBUFFER, scene_fbo_);
  gl_.BindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
  gl_.BlitFramebuffer(0, 0, width, height, 0, 0, width, height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  gl_.BindFramebuffer(GL_FRAMEBUFFER, target);
  gl_.Viewport(0, 0, width, height);
  if (quality == RenderQuality::Full) smooth_edges(scene, view_projection);

  // The flat layer goes over the smoothed picture: text stays sharp, and its shapes carry their
  // own feathered edges.
  Overlay overlay(text.atlas);
  annotate(overlay, scene, view_projection, width, height);
  gl_.Enable(GL_BLEND);
  gl_.BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  draw_overlay(overlay.vertices(), text, width, height);
  gl_.Disable(GL_BLEND);
  gl_.BindVertexArray(0);
  gl_.BindFramebuffer(GL_FRAMEBUFFER, 0);
}

void Renderer::smooth_edges(const Scene& scene, const glm::mat4& view_projection) {
  // Only the bodies' edges need it (the ground grid is anti-aliased in its shader), so only the
  // rectangle they cover on screen is smoothed; the rest was copied as it is.
  glm::vec2 lo(1e9f), hi(-1e9f);
  auto cover = [&](const sim::Pose& pose, glm::vec3 half) {
    const glm::mat4 to_clip = view_projection * transform(pose, half * 2.0f);
    for (int i = 0; i < 8; ++i) {
      const glm::vec4 c =
          to_clip * glm::vec4((i & 1) ? 0.5f : -0.5f, (i & 2) ? 0.5f : -0.5f, (i & 4) ? 0.5f : -0.5f, 1);
      if (c.w <= 1e-6f) {  // behind the camera: smooth everything
        lo = glm::vec2(-1), hi = glm::vec2(1);
        return;
      }
      lo = glm::min(lo, glm::vec2(c) / c.w);
      hi = glm::max(hi, glm::vec2(c) / c.w);
    }
  };
  for (const SceneModule& m : scene.modules) cover(m.pose, glm::vec3(kOutlineScale * 0.5f));
  for (const SceneProp& p : scene.props) cover(p.pose, half_extent(p));
  if (lo.x > hi.x) return;  // nothing drawn
  const int x0 = std::clamp(int((lo.x + 1) * 0.5f * float(width_)) - 2, 0, width_);
  const int y0 = std::clamp(int((lo.y + 1) * 0.5f * float(height_)) - 2, 0, height_);
  const int x1 = std::clamp(int((hi.x + 1) * 0.5f * float(width_)) + 3, 0, width_);
  const int y1 = std::clamp(int((hi.y + 1) * 0.5f * float(height_)) + 3, 0, height_);
  if (x1 <= x0 || y1 <= y0) return;
  gl_.Enable(GL_SCISSOR_TEST);
  gl_.Scissor(x0, y0, x1 - x0, y1 - y0);
  const Program& p = *fxaa_program_;
  gl_.UseProgram(p.id);
  gl_.Uniform1i(p.at("u_color"), 0);
  gl_.Uniform2f(p.at("u_texel"), 1.0f / float(width_), 1.0f / float(height_));
  gl_.ActiveTexture(GL_TEXTURE0);
  gl_.BindTexture(GL_TEXTURE_2D, scene_color_);
  gl_.BindVertexArray(empty_vao_);
  gl_.DrawArrays(GL_TRIANGLES, 0, 3);
  gl_.Disable(GL_SCISSOR_TEST);
}

void Renderer::draw_bodies(const Scene& scene, const Camera& camera, const glm::mat4& view_projection,
                           RenderQuality quality) {
  gl_.ClearColor(kBackground.r, kBackground.g, kBackground.b, 1);
  gl_.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
  gl_.Enable(GL_DEPTH_TEST);
  gl_.DepthFunc(GL_LEQUAL);
  gl_.Disable(GL_BLEND);
  gl_.Enable(GL_CULL_FACE);
  gl_.CullFace(GL_BACK);

  // Solid: every module, or with groups highlighted only theirs and the selected one;
  // translucent: the others, near to far (see below). The group's modules and the selected one
  // get a rim.
  const bool highlighting = !scene.groups.empty() || scene.fade_others;
  const bool moving = quality == RenderQuality::Moving;
  const std::vector<bool> hidden = moving ? enclosed_modules(scene) : std::vector<bool>();
  std::vector<Instance> solid, faded, outline, props;
  std::vector<std::pair<float, size_t>> depth;
  for (size_t i = 0; i < scene.modules.size(); ++i) {
    const SceneModule& m = scene.modules[i];
    if (!shown(scene, m)) continue;
    if (!highlighting || m.highlighted || m.selected) {
      if (moving && !(highlighting && m.highlighted) && !m.selected && hidden[i]) continue;
      solid.push_back({transform(m.pose, glm::vec3(kModuleScale)), {m.color.r, m.color.g, m.color.b, 1}});
      // The selection's ring is drawn over everything afterwards (draw_selection).
      if (highlighting && m.highlighted) outline.push_back({transform(m.pose, glm::vec3(kOutlineScale)), kOutline});
    } else if (moving) {
      if (hidden[i]) continue;
      // Opaque, as pale as it looks translucent over the background.
      const glm::vec4 translucent = dimmed(m.color);
      const glm::vec3 seen = glm::mix(kBackground, glm::vec3(translucent), translucent.a);
      faded.push_back({transform(m.pose, glm::vec3(kModuleScale)), glm::vec4(seen, 1)});
    } else {
      const auto& p = m.pose.position;
      depth.push_back({glm::length(glm::vec3(p[0], p[1], p[2]) - camera.eye), faded.size()});
      faded.push_back({transform(m.pose, glm::vec3(kModuleScale)), dimmed(m.color)});
    }
  }
  std::sort(depth.begin(), depth.end());
  std::vector<Instance> near_to_far;
  near_to_far.reserve(faded.size());
  for (const auto& [d, i] : depth) near_to_far.push_back(faded[i]);
  if (moving) near_to_far = std::move(faded);  // opaque: any order

  // Translucent modules blend over the ground, so it goes first; with nothing translucent it goes
  // last, after the solids near to far, and the depth test skips the pixels they hide before
  // shading them (the picture is the same: each pixel keeps its nearest surface).
  const bool translucent = highlighting;
  if (translucent) draw_ground(scene, view_projection);
  const Program& p = *mesh_program_;
  gl_.UseProgram(p.id);
  gl_.UniformMatrix4fv(p.at("u_view_projection"), 1, GL_FALSE, glm::value_ptr(view_projection));
  const glm::vec3 light = glm::normalize(glm::normalize(camera.eye - camera.target) + glm::vec3(0.3f, 0.1f, 1.2f));
  gl_.Uniform3fv(p.at("u_light"), 1, glm::value_ptr(light));
  const Mesh& module_mesh = *meshes_.at(scene.module_shape);

  // Props and, with nothing highlighted, every module: solid.
  gl_.Uniform1i(p.at("u_unlit"), 0);
  for (const SceneProp& prop : scene.props) {
    props.assign(1, {transform(prop.pose, 2.0f * half_extent(prop)), {kPropColor.r, kPropColor.g, kPropColor.b, 1}});
    draw_instances(*meshes_.at(prop.shape), props);
  }
  if (!translucent) {
    const auto distance = [&](const Instance& i) { return glm::length(glm::vec3(i.model[3]) - camera.eye); };
    std::vector<std::pair<float, size_t>> solid_depth;
    solid_depth.reserve(solid.size());
    for (size_t i = 0; i < solid.size(); ++i) solid_depth.push_back({distance(solid[i]), i});
    std::sort(solid_depth.begin(), solid_depth.end());
    std::vector<Instance> solid_near_to_far;
    solid_near_to_far.reserve(solid.size());
    for (const auto& [d, i] : solid_depth) solid_near_to_far.push_back(solid[i]);
    draw_instances(module_mesh, solid_near_to_far);
    draw_ground(scene, view_projection);
    return;
  }

  // The group, marked in the stencil buffer: first a grown flat copy of each of its modules,
  // writing no depth, then the modules over it, which leaves an even rim around their silhouettes.
  gl_.Enable(GL_STENCIL_TEST);
  gl_.StencilFunc(GL_ALWAYS, 1, 0xff);
  gl_.StencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
  gl_.Uniform1i(p.at("u_unlit"), 1);
  gl_.DepthMask(GL_FALSE);
  draw_instances(module_mesh, outline);
  gl_.DepthMask(GL_TRUE);
  gl_.Uniform1i(p.at("u_unlit"), 0);
  draw_instances(module_mesh, solid);

  // The others, translucent, kept off the group's pixels, so that no module veils it however deep
  // inside the ensemble it lies. Near to far with depth written, each pixel takes only the nearest
  // layer: the ensemble reads as a pale shell, and a frame costs one layer, not ten.
  gl_.StencilFunc(GL_NOTEQUAL, 1, 0xff);
  gl_.StencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
  if (!moving) gl_.Enable(GL_BLEND);
  gl_.BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  draw_instances(module_mesh, near_to_far);
  gl_.Disable(GL_BLEND);
  gl_.Disable(GL_STENCIL_TEST);
}

void Renderer::draw_selection(const Scene& scene) {
  const auto selected =
      std::find_if(scene.modules.begin(), scene.modules.end(), [](const SceneModule& m) { return m.selected; });
  if (selected == scene.modules.end()) return;
  // Over whatever covers it, with no depth test (a box, a cylinder and a sphere are convex: culling
  // their back faces draws them right in any order): the module itself, marked in the stencil
  // buffer, then a grown flat copy kept off its pixels, which leaves a ring around its silhouette.
  const std::vector<Instance> module{{transform(selected->pose, glm::vec3(kModuleScale)),
                                      {selected->color.r, selected->color.g, selected->color.b, 1}}};
  const std::vector<Instance> ring{{transform(selected->pose, glm::vec3(kSelectionScale)), kSelectedOutline}};
  const Program& p = *mesh_program_;
  const Mesh& mesh = *meshes_.at(scene.module_shape);
  gl_.UseProgram(p.id);
  gl_.Disable(GL_DEPTH_TEST);
  gl_.Disable(GL_BLEND);
  gl_.Enable(GL_CULL_FACE);
  gl_.Enable(GL_STENCIL_TEST);
  gl_.Clear(GL_STENCIL_BUFFER_BIT);
  gl_.StencilFunc(GL_ALWAYS, 2, 0xff);
  gl_.StencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
  gl_.Uniform1i(p.at("u_unlit"), 0);
  draw_instances(mesh, module);
  gl_.StencilFunc(GL_NOTEQUAL, 2, 0xff);
  gl_.StencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
  gl_.Uniform1i(p.at("u_unlit"), 1);
  draw_instances(mesh, ring);
  gl_.Uniform1i(p.at("u_unlit"), 0);
  gl_.Disable(GL_STENCIL_TEST);
}

Image Renderer::render(const Scene& scene, int width, int height, RenderQuality quality) {
  resize(width, height);  // makes the output framebuffer
  draw(scene, width, height, output_fbo_, quality);
  Image image = read_framebuffer(gl_, output_fbo_, width, height);
  if (GLenum error = gl_.GetError(); error != GL_NO_ERROR)
    throw RenderError("OpenGL error " + std::to_string(error) + " while drawing");
  return image;
}

}  // namespace dw::render
