#include "render/annotations.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

#include "render/palette.h"

namespace dw::render {
namespace {

constexpr glm::vec4 kInk{0.13f, 0.14f, 0.16f, 1};
constexpr glm::vec4 kLink{0.84f, 0.11f, 0.16f, 1};  // slot links and label rings
constexpr glm::vec4 kPaper{1, 1, 1, 1};
constexpr glm::vec4 kPanel{1, 1, 1, 0.88f};
constexpr glm::vec4 kContact{0.95f, 0.1f, 0.85f, 1};  // contact points and normals

// The contact points (Scene::contacts) as discs, each with its normal: a stem from the point, as
// long as half a module for the largest impulse of the step and a quarter for none, so that which
// contacts bear the weight reads at a glance. Over the modules, as the selection is: a contact is
// mostly where two bodies hide it. Only those touching a module that is drawn (Isolate, the cut).
void draw_contacts(Overlay& o, const Scene& scene, const glm::mat4& view_projection, int width, int height,
                   const std::unordered_map<sim::ModuleId, const SceneModule*>& by_id) {
  float largest = 0;
  for (const SceneContact& c : scene.contacts) largest = std::max(largest, c.impulse);
  const float t = o.font().pixel_height();
  auto drawn = [&](uint32_t who) {
    auto it = by_id.find(who);
    return it != by_id.end() && shown(scene, *it->second);
  };
  for (const SceneContact& c : scene.contacts) {
    if (!drawn(c.a) && !drawn(c.b)) continue;
    const glm::vec3 p(c.point[0], c.point[1], c.point[2]), n(c.normal[0], c.normal[1], c.normal[2]);
    const float length = 0.25f + (largest > 0 ? 0.25f * c.impulse / largest : 0);
    const auto at = project(view_projection, p, width, height);
    const auto tip = project(view_projection, p + n * length, width, height);
    if (!at) continue;
    if (tip) {
      o.line(*at, *tip, t * 0.2f, kPaper);
      o.line(*at, *tip, t * 0.1f, kContact);
    }
    o.disc(*at, t * 0.2f, kPaper);
    o.disc(*at, t * 0.14f, kContact);
  }
}

glm::vec4 rgba(Color c) { return {c.r, c.g, c.b, 1}; }

// The line under the title naming the first group: "two_leaders at t=12: a=4 b=5 c=9".
std::string group_caption(const Scene& scene) {
  if (scene.groups.empty()) return {};
  const SceneGroup& g = scene.groups.front();
  std::string s = g.watch + " at t=" + std::to_string(g.t) + ":";
  for (size_t i = 0; i < g.modules.size(); ++i)
    s += " " + (i < g.slot_names.size() ? g.slot_names[i] : "?") + "=" + std::to_string(g.modules[i]);
  if (scene.groups.size() > 1) s += "   (+" + std::to_string(scene.groups.size() - 1) + " more)";
  return s;
}

struct LegendBox {
  glm::vec2 min, max;
};

// The legend's panel, under the title; its size follows its entries.
LegendBox legend_box(const Scene& scene, const FontAtlas& font, int height) {
  const float t = font.pixel_height();
  const float top = t * (scene.groups.empty() ? 2.4f : 3.8f);
  float text = font.text_width(scene.legend.title);
  for (const LegendEntry& e : scene.legend.entries) text = std::max(text, t * 1.6f + font.text_width(e.label));
  const float rows = scene.legend.gradient ? 6.0f : float(scene.legend.entries.size());
  const float bottom = std::min(float(height) - t, top + t * (2.2f + rows * 1.35f));
  return {{t * 0.8f, top}, {t * 0.8f + text + t * 1.4f, bottom}};
}

void draw_legend(Overlay& o, const Scene& scene, int height) {
  const FontAtlas& font = o.font();
  const float t = font.pixel_height();
  const LegendBox box = legend_box(scene, font, height);
  o.rect(box.min, box.max, kPanel);
  const float x = box.min.x + t * 0.7f;
  float y = box.min.y + t * 1.5f;
  o.text({x, y}, scene.legend.title, kInk);
  y += t * 0.8f;
  const auto& entries = scene.legend.entries;
  if (!scene.legend.gradient) {
    for (const LegendEntry& e : entries) {
      o.rect({x, y + t * 0.2f}, {x + t, y + t * 1.2f}, rgba(e.color));
      o.text({x + t * 1.6f, y + t * 1.05f}, e.label, kInk);
      y += t * 1.35f;
    }
    return;
  }
  // A bar from the largest value (top) to the smallest, labelled at each stop.
  const float bar_top = y + t * 0.5f, bar_height = t * 1.35f * 5.0f;
  constexpr int kSlices = 48;
  for (int i = 0; i < kSlices; ++i) {
    const float s0 = float(i) / kSlices, s1 = float(i + 1) / kSlices;
    o.rect({x, bar_top + bar_height * s0}, {x + t, bar_top + bar_height * s1 + 0.5f},
           rgba(gradient_color(1.0 - (s0 + s1) * 0.5)));
  }
  for (size_t i = 0; i < entries.size(); ++i) {
    const float s = entries.size() > 1 ? float(i) / float(entries.size() - 1) : 0;
    const float at = bar_top + bar_height * (1 - s);
    o.rect({x + t, at - 0.5f}, {x + t * 1.3f, at + 0.5f}, kInk);
    o.text({x + t * 1.6f, at + t * 0.35f}, entries[i].label, kInk);
  }
}

}  // namespace

int text_size(int height, int least) { return std::clamp(height / 30, least, std::max(least, 40)); }

Region view_region(const Scene& scene, const FontAtlas& font, int width, int height) {
  Region r;
  const float t = font.pixel_height();
  r.top = std::min(0.4f, t * (scene.groups.empty() ? 2.0f : 3.4f) / float(height));
  r.bottom = 1 - std::min(0.2f, t * 0.6f / float(height));
  if (!scene.legend.title.empty())
    r.left = std::min(0.4f, (legend_box(scene, font, height).max.x + t * 0.5f) / float(width));
  r.right = 1 - std::min(0.2f, t * 0.6f / float(width));
  return r;
}

std::optional<glm::vec2> project(const glm::mat4& view_projection, glm::vec3 point, int width, int height) {
  const glm::vec4 clip = view_projection * glm::vec4(point, 1);
  if (clip.w <= 1e-6f) return std::nullopt;
  const glm::vec2 ndc = glm::vec2(clip) / clip.w;
  return glm::vec2((ndc.x + 1) * 0.5f * float(width), (1 - ndc.y) * 0.5f * float(height));
}

std::optional<EdgePointer> edge_pointer(const glm::mat4& view_projection, glm::vec3 point, int width, int height,
                                        float inset) {
  const glm::vec4 clip = view_projection * glm::vec4(point, 1);
  if (clip.w > 1e-6f) {
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    const glm::vec2 pixel((ndc.x + 1) * 0.5f * float(width), (1 - ndc.y) * 0.5f * float(height));
    if (pixel.x >= 0 && pixel.y >= 0 && pixel.x < float(width) && pixel.y < float(height)) return std::nullopt;
  }
  // From the centre, in pixels' directions (y down): clip x and y keep the side a point lies on,
  // also behind the camera, where dividing by w (< 0) mirrors the projection.
  glm::vec2 dir(clip.x * float(width), -clip.y * float(height));
  if (glm::length(dir) < 1e-9f) dir = glm::vec2(0, 1);  // straight behind: below
  dir = glm::normalize(dir);
  const glm::vec2 centre(float(width) * 0.5f, float(height) * 0.5f);
  const float hx = std::max(1.0f, centre.x - inset), hy = std::max(1.0f, centre.y - inset);
  const float reach = std::min(std::abs(dir.x) > 1e-9f ? hx / std::abs(dir.x) : 1e30f,
                               std::abs(dir.y) > 1e-9f ? hy / std::abs(dir.y) : 1e30f);
  return EdgePointer{centre + dir * reach, dir};
}

std::vector<std::optional<glm::vec2>> place_labels(const std::vector<std::optional<glm::vec2>>& tops,
                                                   const std::vector<std::optional<glm::vec2>>& wanted, float radius,
                                                   const std::vector<Box>& keep_clear) {
  std::vector<std::optional<glm::vec2>> placed(tops.size());
  const float apart = 2 * radius + std::max(2.0f, radius * 0.25f);  // centre to centre
  auto free = [&](glm::vec2 p) {
    for (const auto& q : placed)
      if (q && glm::distance(*q, p) < apart) return false;
    for (const Box& b : keep_clear)
      if (glm::distance(glm::clamp(p, b.min, b.max), p) < radius + 1) return false;
    return true;
  };
  for (size_t i = 0; i < tops.size(); ++i) {
    if (!tops[i] || !wanted[i]) continue;
    if (free(*wanted[i])) {
      placed[i] = wanted[i];
      continue;
    }
    // Rings around the module, from the stem's direction (up) outwards, alternately right and left.
    const glm::vec2 up = *wanted[i] - *tops[i];
    const float stem = std::max(glm::length(up), radius * 1.5f);
    const float base = glm::length(up) > 1e-3f ? std::atan2(up.y, up.x) : -1.5707964f;
    for (int ring = 0; ring < 40 && !placed[i]; ++ring) {
      const float reach = stem + float(ring) * apart * 0.5f;
      for (int k = 0; k < 12 && !placed[i]; ++k) {
        const float turn = float((k + 1) / 2) * 0.5236f * (k % 2 ? 1.0f : -1.0f);  // 0, ±30°, ±60°...
        const glm::vec2 p = *tops[i] + reach * glm::vec2(std::cos(base + turn), std::sin(base + turn));
        if (free(p)) placed[i] = p;
      }
    }
    if (!placed[i]) placed[i] = wanted[i];  // a crowd no ring clears: overlapping beats missing
  }
  return placed;
}

void annotate(Overlay& o, const Scene& scene, const glm::mat4& view_projection, int width, int height) {
  const FontAtlas& font = o.font();
  const float t = font.pixel_height();

  // Slot links and labels. A label floats above its module, on a short stem, so that it covers
  // neither the module nor the links.
  std::unordered_map<sim::ModuleId, const SceneModule*> by_id;
  for (const SceneModule& m : scene.modules) by_id[m.id] = &m;
  // What the labels keep off: the title, the group's caption (written after them, over the
  // labels, it still read under their discs) and the legend.
  const std::string caption = group_caption(scene);
  std::vector<Box> keep_clear{{{t * 0.8f, t * 0.3f}, {t * 0.8f + font.text_width(scene.title), t * 1.75f}}};
  if (!caption.empty()) keep_clear.push_back({{t * 0.8f, t * 1.75f}, {t * 0.8f + font.text_width(caption), t * 3.15f}});
  if (!scene.legend.title.empty()) {
    const LegendBox legend = legend_box(scene, font, height);
    keep_clear.push_back({legend.min, legend.max});
  }
  draw_contacts(o, scene, view_projection, width, height, by_id);
  for (const SceneGroup& g : scene.groups) {
    std::vector<std::optional<glm::vec2>> top(g.modules.size()), label(g.modules.size());
    for (size_t i = 0; i < g.modules.size(); ++i) {
      auto it = by_id.find(g.modules[i]);
      if (it == by_id.end()) continue;
      const auto& p = it->second->pose.position;
      top[i] = project(view_projection, {p[0], p[1], p[2] + 0.5f}, width, height);
      label[i] = project(view_projection, {p[0], p[1], p[2] + 1.4f}, width, height);
    }
    label = place_labels(top, label, t * 0.72f, keep_clear);
    for (size_t i = 0; i + 1 < g.modules.size(); ++i) {
      if (!top[i] || !top[i + 1]) continue;
      o.line(*top[i], *top[i + 1], t * 0.42f, kPaper);
      o.line(*top[i], *top[i + 1], t * 0.22f, kLink);
    }
    for (size_t i = 0; i < g.modules.size(); ++i) {
      if (!top[i]) continue;
      o.disc(*top[i], t * 0.28f, kLink);
      if (!label[i]) continue;
      o.line(*top[i], *label[i], t * 0.12f, kLink);
      const float r = t * 0.72f;
      o.disc(*label[i], r, kLink);
      o.disc(*label[i], r - std::max(1.5f, t * 0.12f), kPaper);
      const std::string name = i < g.slot_names.size() ? g.slot_names[i] : "?";
      const float w = font.text_width(name);
      o.text({label[i]->x - w * 0.5f, label[i]->y + font.ascent() * 0.36f}, name, kInk);
    }
  }

  // Title, and the first group under it.
  o.text({t * 0.8f, t * 1.45f}, scene.title, kInk);
  if (!caption.empty()) o.text({t * 0.8f, t * 2.85f}, caption, kLink);

  if (!scene.legend.title.empty()) draw_legend(o, scene, height);
}

}  // namespace dw::render
