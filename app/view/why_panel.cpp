// The Why panel (docs/view.md, docs/why.md): the session's `why` answer (docs/design.md §7b) drawn
// as a space-time diagram in the style of ShiViz — a column per module of the cone, steps
// downward, a dot per event, an arrow per message — scrolled and zoomed as the timeline is; a
// click on a dot goes to its step and selects its module. The 3D view lights the cone's modules
// that have an event at the current step and draws the messages read at it, so that scrubbing the
// timeline shows the cause travelling. The answer is the session's; this file only draws it.
#include <imgui.h>

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <sstream>

#include "app/view/debugger.h"
#include "app/view/widgets.h"
#include "render/annotations.h"
#include "shell/command.h"

namespace dw::view {
namespace {

// The diagram's colours (tests/app/view/window_why_test.cpp looks for them on the pixels).
constexpr ImU32 kBackground = IM_COL32(30, 31, 36, 255);
constexpr ImU32 kStripe = IM_COL32(38, 39, 46, 255);
constexpr ImU32 kColumnLine = IM_COL32(95, 97, 108, 255);
constexpr ImU32 kGroupLine = IM_COL32(190, 80, 70, 255);
constexpr ImU32 kMessage = IM_COL32(110, 205, 255, 255);
constexpr ImU32 kSteadyMessage = IM_COL32(70, 120, 150, 255);  // the words of a step before
constexpr ImU32 kLink = IM_COL32(200, 200, 200, 255);          // a cause through dropped events
constexpr ImU32 kChanged = IM_COL32(250, 200, 60, 255);
constexpr ImU32 kOrigin = IM_COL32(255, 105, 50, 255);
constexpr ImU32 kUnchanged = IM_COL32(160, 160, 165, 255);
constexpr ImU32 kOutside = IM_COL32(225, 110, 235, 255);  // an action, intervention or [[event]]
constexpr ImU32 kHover = IM_COL32(255, 255, 255, 255);
constexpr float kDot = 6;  // a dot's radius

// A line with an arrowhead at its end, stopping `gap` short of both points (the dots).
void arrow(ImDrawList* draw, ImVec2 a, ImVec2 b, ImU32 color, float thickness, float gap, bool dashed = false) {
  const float dx = b.x - a.x, dy = b.y - a.y, length = std::hypot(dx, dy);
  if (length < 2 * gap + 4) return;
  const ImVec2 u(dx / length, dy / length);
  const ImVec2 from(a.x + u.x * gap, a.y + u.y * gap), to(b.x - u.x * gap, b.y - u.y * gap);
  const float head = 4 + 2 * thickness;
  const ImVec2 base(to.x - u.x * head, to.y - u.y * head);
  if (dashed) {
    const float run = std::hypot(base.x - from.x, base.y - from.y);
    for (float s = 0; s < run; s += 9) {
      const float e = std::min(run, s + 5);
      draw->AddLine(ImVec2(from.x + u.x * s, from.y + u.y * s), ImVec2(from.x + u.x * e, from.y + u.y * e), color,
                    thickness);
    }
  } else {
    draw->AddLine(from, base, color, thickness);
  }
  draw->AddTriangleFilled(to, ImVec2(base.x - u.y * head * 0.5f, base.y + u.x * head * 0.5f),
                          ImVec2(base.x + u.y * head * 0.5f, base.y - u.x * head * 0.5f), color);
}

// A `why` line without its options: what the panel asks again with its own.
std::string without_options(const std::string& line, bool& narrow, int& depth) {
  std::istringstream in(line);
  std::string word, kept;
  while (in >> word) {
    if (word == "--narrow") {
      narrow = true;
      continue;
    }
    if (word == "--depth") {
      if (in >> word) depth = std::clamp(std::atoi(word.c_str()), 0, 64);
      continue;
    }
    kept += (kept.empty() ? "" : " ") + word;
  }
  return kept;
}

// Where the diagram is drawn: its frame [p0, p1) under the column names (from origin's row) and
// right of the step numbers, scrolled and zoomed by the view.
struct Frame {
  const WhyDiagram& d;
  const WhyView& v;
  ImVec2 origin, p0, p1;
  ImVec2 at(int column, int64_t t) const { return ImVec2(p0.x + v.x_of(column), p0.y + v.y_of(t, d.first)); }
  // A write from outside the programs comes at the start of its step, before them: above.
  ImVec2 dot_at(const WhyDot& dot) const {
    const ImVec2 c = at(dot.column, dot.step);
    return dot.writer == "program" || dot.writer == "initial" ? c : ImVec2(c.x, c.y - v.step_height * 0.3f);
  }
};

// The frame's background: a stripe every other step, a line down each module's column (the
// group's red), the current step's row lit as the timeline's cursor.
void draw_grid(ImDrawList* draw, const Frame& f, int64_t current) {
  const WhyView& v = f.v;
  draw->AddRectFilled(f.p0, f.p1, kBackground);
  for (int64_t t = f.d.first; t <= f.d.last; t += 2) {
    const float y = f.at(0, t).y - v.step_height / 2;
    draw->AddRectFilled(ImVec2(f.p0.x, y), ImVec2(f.p1.x, y + v.step_height), kStripe);
  }
  for (size_t c = 0; c < f.d.modules.size(); ++c) {
    const bool group = f.d.group_column[c];
    draw->AddLine(ImVec2(f.at(int(c), f.d.first).x, f.at(int(c), f.d.first).y - v.step_height / 2),
                  ImVec2(f.at(int(c), f.d.last).x, f.at(int(c), f.d.last).y + v.step_height / 2),
                  group ? kGroupLine : kColumnLine, group ? 2.0f : 1.0f);
  }
  if (current >= f.d.first && current <= f.d.last) {
    const float y = f.at(0, current).y;
    draw->AddRectFilled(ImVec2(f.p0.x, y - v.step_height / 2), ImVec2(f.p1.x, y + v.step_height / 2),
                        IM_COL32(255, 255, 255, 22));
    draw->AddLine(ImVec2(f.p0.x, y), ImVec2(f.p1.x, y), IM_COL32(255, 255, 255, 90), 1);
  }
}

// The column names above (the group's in red), the steps on the left. Columns scrolled out of the
// frame are counted at its edges (a right drag brings them in), the names kept clear of that.
void draw_scales(ImDrawList* draw, const Frame& f, int64_t current) {
  const WhyView& v = f.v;
  const float width = f.p1.x - f.p0.x, line = ImGui::GetTextLineHeight();
  const int hidden_left = int(std::floor(v.scroll_x / v.column_width + 0.01f));
  const int hidden_right =
      std::max(0, int(f.d.modules.size()) - int(std::floor((v.scroll_x + width) / v.column_width + 0.01f)));
  const ImU32 faint = ImGui::GetColorU32(ImGuiCol_TextDisabled);
  float names_from = f.p0.x - 2, names_to = f.p1.x + 2;
  if (hidden_left > 0) {
    const std::string more = "< " + std::to_string(hidden_left);
    draw->AddText(ImVec2(f.p0.x, f.origin.y + 2), faint, more.c_str());
    names_from = f.p0.x + ImGui::CalcTextSize(more.c_str()).x + 6;
  }
  if (hidden_right > 0) {
    const std::string more = std::to_string(hidden_right) + " more >";
    const float w = ImGui::CalcTextSize(more.c_str()).x;
    draw->AddText(ImVec2(f.p1.x - w, f.origin.y + 2), faint, more.c_str());
    names_to = f.p1.x - w - 6;
  }
  for (size_t c = 0; c < f.d.modules.size(); ++c) {
    const std::string name = std::to_string(f.d.modules[c]);
    const float x = f.at(int(c), f.d.first).x - ImGui::CalcTextSize(name.c_str()).x / 2;
    if (x < names_from || x + ImGui::CalcTextSize(name.c_str()).x > names_to) continue;
    draw->AddText(ImVec2(x, f.origin.y + 2),
                  f.d.group_column[c] ? IM_COL32(240, 120, 105, 255) : ImGui::GetColorU32(ImGuiCol_Text), name.c_str());
  }
  const int64_t every = std::max<int64_t>(1, int64_t(std::ceil((line + 2) / v.step_height)));
  for (int64_t t = f.d.first; t <= f.d.last; t += every) {
    const float y = f.at(0, t).y - line / 2;
    if (y < f.p0.y - 1 || y + line > f.p1.y + 1) continue;
    const std::string step = std::to_string(t);
    draw->AddText(ImVec2(f.p0.x - 6 - ImGui::CalcTextSize(step.c_str()).x, y),
                  t == current ? IM_COL32(255, 255, 255, 255) : faint, step.c_str());
  }
}

}  // namespace

void Debugger::show_why(const nlohmann::ordered_json& answer, const std::string& line) {
  auto diagram = why_diagram(answer, line);
  if (!diagram) return;
  why_ = std::move(diagram);
  status("why: " + why_->title);
  why_open_ = true;
  why_view_.fitted = true;
  bool narrow = false;
  int depth = 3;
  why_asked_ = without_options(line, narrow, depth);
  why_narrow_ = narrow;
  why_depth_ = depth;
}

void Debugger::ask_why(const std::string& line) {
  bool narrow = false;
  int depth = 3;
  const std::string base = without_options(line, narrow, depth);
  model_.playing = false;
  send(base + (why_depth_ != 3 ? " --depth " + std::to_string(why_depth_) : "") + (why_narrow_ ? " --narrow" : ""));
}

void Debugger::why_last_changed() {
  if (!model_.selected || !readout_.inspector || readout_.at.current < 0) {
    status("Y asks why of the selected module's last changed variable: select a module first", true);
    return;
  }
  const sim::Model& m = session_.model();
  const sim::ModuleId module = *model_.selected;
  const int64_t now = readout_.at.current;
  const size_t columns = m.variable_count();
  // The latest step at or before now where some variable changed, from the module's history;
  // among its changes the first not hidden ('_'), else the first.
  std::optional<size_t> chosen;
  worker_->try_read([&](sim::Session&) {
    if (!module_window_ || module_window_->module != module || now > module_window_->to) return;
    const ModuleWindow& w = *module_window_;
    for (int64_t t = now; t > w.from && !chosen; --t) {
      const auto row = [&](int64_t s) { return w.rows.begin() + std::ptrdiff_t(size_t(s - w.from) * columns); };
      for (size_t c = 0; c < columns; ++c)
        if (row(t)[std::ptrdiff_t(c)] != row(t - 1)[std::ptrdiff_t(c)] &&
            (!chosen || (m.universe.variables[*chosen][0] == '_' && m.universe.variables[c][0] != '_')))
          chosen = c;
    }
  });
  if (!chosen)
    for (size_t c = 0; c < readout_.inspector->variables.size() && !chosen; ++c)
      if (readout_.inspector->variables[c].changed()) chosen = c;
  ask_why("why " + std::to_string(module) + " " + m.universe.variables[chosen.value_or(0)] + " " + std::to_string(now));
}

void Debugger::why_panel() {
  why_drawn_ = {{"open", why_open_ && why_.has_value()}};
  if (!why_open_ || !why_) return;
  place(panels_.why);
  bool open = true;
  ImGui::Begin("Why", &open, ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse);
  const WhyDiagram& d = *why_;
  ImGui::TextWrapped("%s", d.title.c_str());
  // Asked again with other options: narrow (only the changes and the new messages) and depth.
  if (ImGui::Checkbox("narrow", &why_narrow_)) ask_why(why_asked_);
  note_widget("narrow");
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("Only the events that changed a variable or sent a new message, linked through the others");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(90);
  if (ImGui::InputInt("depth", &why_depth_)) {
    why_depth_ = std::clamp(why_depth_, 0, 64);
    ask_why(why_asked_);
  }
  flow(button_width("fit"));
  if (button("fit", true)) why_view_.fitted = true;
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("The whole diagram again (wheel: zoom the steps, right drag: pan)");
  ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetColorU32(ImGuiCol_TextDisabled));
  ImGui::TextWrapped(
      "dot: an event (filled: it changed a variable; hover: what), arrow: a message (hover: its "
      "words); click a dot to go there");
  ImGui::PopStyleColor();
  why_diagram_canvas(d);
  ImGui::End();
  if (!open) why_open_ = false;
}

void Debugger::why_diagram_canvas(const WhyDiagram& d) {
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const ImVec2 origin = ImGui::GetCursorScreenPos(), avail = ImGui::GetContentRegionAvail();
  const float margin = ImGui::CalcTextSize(std::to_string(d.last).c_str()).x + 12;
  const ImVec2 p0(origin.x + margin, origin.y + ImGui::GetTextLineHeight() + 6),
      p1(origin.x + avail.x, origin.y + avail.y - 2);
  const float width = std::max(10.0f, p1.x - p0.x), height = std::max(10.0f, p1.y - p0.y);
  if (why_view_.fitted) why_view_.fit(d, width, height);
  why_view_.clamp(d, width, height);
  const Frame f{d, why_view_, origin, p0, p1};
  const ImVec2 mouse = ImGui::GetIO().MousePos;
  const bool inside =
      ImGui::IsWindowHovered() && mouse.x >= p0.x && mouse.x < p1.x && mouse.y >= p0.y && mouse.y < p1.y;
  // What the mouse is over: a dot first, else the nearest arrow within a few pixels.
  std::optional<size_t> hovered_dot, hovered_arrow;
  if (inside) {
    for (size_t i = 0; i < d.dots.size(); ++i) {
      const ImVec2 c = f.dot_at(d.dots[i]);
      if (std::hypot(mouse.x - c.x, mouse.y - c.y) <= kDot + 2) hovered_dot = i;
    }
    float best = 5;
    for (size_t i = 0; i < d.arrows.size() && !hovered_dot; ++i) {
      const ImVec2 a = f.at(d.arrows[i].from_column, d.arrows[i].sent),
                   b = f.at(d.arrows[i].to_column, d.arrows[i].read);
      const float dist = distance_to_segment(mouse.x, mouse.y, a.x, a.y, b.x, b.y);
      if (dist < best) best = dist, hovered_arrow = i;
    }
  }

  draw->PushClipRect(p0, p1, true);
  draw_grid(draw, f, readout_.at.current);
  why_drawn_["frame"] = {p0.x, p0.y, p1.x, p1.y};
  why_drawn_["title"] = d.title;
  why_drawn_["command"] = d.command;
  why_drawn_["arrows"] = nlohmann::ordered_json::array();
  for (size_t i = 0; i < d.arrows.size(); ++i) {
    const WhyArrow& a = d.arrows[i];
    const ImVec2 from = f.at(a.from_column, a.sent), to = f.at(a.to_column, a.read);
    const ImU32 color = hovered_arrow == i ? kHover : !a.message ? kLink : a.is_new ? kMessage : kSteadyMessage;
    arrow(draw, from, to, color, hovered_arrow == i ? 3.0f : 2.0f, kDot + 1, !a.message);
    why_drawn_["arrows"].push_back({{"from", d.modules[size_t(a.from_column)]},
                                    {"to", d.modules[size_t(a.to_column)]},
                                    {"sent", a.sent},
                                    {"read", a.read},
                                    {"message", a.message},
                                    {"line", {from.x, from.y, to.x, to.y}}});
  }
  why_drawn_["dots"] = nlohmann::ordered_json::array();
  for (size_t i = 0; i < d.dots.size(); ++i) {
    const WhyDot& dot = d.dots[i];
    const ImVec2 c = f.dot_at(dot);
    const float r = dot.origin ? kDot + 2 : kDot;
    if (dot.writer != "program" && dot.writer != "initial") {
      draw->AddRectFilled(ImVec2(c.x - r, c.y - r), ImVec2(c.x + r, c.y + r), kOutside);
    } else if (dot.changed || dot.origin) {
      draw->AddCircleFilled(c, r, dot.origin ? kOrigin : kChanged, 20);
    } else {
      draw->AddCircleFilled(c, r, kBackground, 20);
      draw->AddCircle(c, r - 1, kUnchanged, 20, 2);
    }
    if (dot.group) draw->AddCircle(c, r + 3, kGroupLine, 20, 2);
    if (hovered_dot == i) draw->AddCircle(c, r + 3, kHover, 20, 2);
    why_drawn_["dots"].push_back({{"module", dot.module},
                                  {"step", dot.step},
                                  {"writer", dot.writer},
                                  {"changed", dot.changed},
                                  {"origin", dot.origin},
                                  {"centre", {c.x, c.y}}});
  }
  draw->PopClipRect();
  draw_scales(draw, f, readout_.at.current);

  // Each dot in sight a button (`press why dot M S`): a click goes to its step and selects it.
  for (size_t i = 0; i < d.dots.size(); ++i) {
    const WhyDot& dot = d.dots[i];
    const ImVec2 c = f.dot_at(dot);
    if (c.x < p0.x || c.x > p1.x || c.y < p0.y || c.y > p1.y) continue;
    ImGui::SetCursorScreenPos(ImVec2(c.x - kDot, c.y - kDot));
    ImGui::PushID(int(i));
    const bool clicked = ImGui::InvisibleButton("##why_dot", ImVec2(2 * kDot, 2 * kDot));
    ImGui::PopID();
    const bool outside = dot.writer != "program" && dot.writer != "initial";
    note_widget("why dot " + std::to_string(dot.module) + " " + std::to_string(dot.step) +
                (outside ? " " + dot.writer : ""));
    if (clicked) {
      const std::optional<sim::ModuleId> m = module_of_id(session_.model().universe, dot.module);
      model_.playing = false;
      if (m) model_.on_module_click(*m);
      readout_stale_ = true;
      if (dot.step != readout_.at.current) apply({command::seek(dot.step)});
    }
  }
  // The rest of the frame: the wheel zooms the steps about the mouse, a right drag pans.
  ImGui::SetCursorScreenPos(p0);
  ImGui::InvisibleButton("##why_canvas", ImVec2(width, height), ImGuiButtonFlags_MouseButtonRight);
  if (inside) {
    const ImGuiIO& io = ImGui::GetIO();
    if (io.MouseWheel != 0) why_view_.zoom(std::pow(1.25f, io.MouseWheel), mouse.y - p0.y);
    if (ImGui::IsMouseDragging(ImGuiMouseButton_Right)) {
      const ImVec2 drag = ImGui::GetMouseDragDelta(ImGuiMouseButton_Right);
      why_view_.pan(drag.x, drag.y);
      ImGui::ResetMouseDragDelta(ImGuiMouseButton_Right);
    }
    if (hovered_dot)
      ImGui::SetTooltip("%s\n(click: go to this step, select the module)", d.dots[*hovered_dot].text.c_str());
    else if (hovered_arrow) ImGui::SetTooltip("%s", d.arrows[*hovered_arrow].text.c_str());
  }
}

void Debugger::why_in_view(ImVec2 origin, ImVec2 scale) {
  if (!why_open_ || !why_ || readout_.scene.modules.empty()) return;
  const WhyDiagram& d = *why_;
  const glm::mat4 vp = renderer_->view_projection(camera_scene(), view_.width, view_.height);
  auto where = [&](uint32_t id) { return module_on_screen(id, vp, origin, scale); };
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const int64_t now = readout_.at.current;
  // The cone's modules: a faint ring each, lit where the cone has an event at this step.
  for (size_t c = 0; c < d.modules.size(); ++c) {
    const auto p = where(d.modules[c]);
    if (!p) continue;
    const bool lit = std::any_of(d.dots.begin(), d.dots.end(),
                                 [&](const WhyDot& dot) { return dot.column == int(c) && dot.step == now; });
    if (lit) {
      draw->AddCircleFilled(*p, 10, IM_COL32(250, 200, 60, 150), 20);
      draw->AddCircle(*p, 11, kChanged, 20, 3);
    } else {
      draw->AddCircle(*p, 8, IM_COL32(250, 200, 60, 120), 20, 1.5f);
    }
  }
  // The messages read at this step, from sender to receiver.
  for (const WhyArrow& a : d.arrows) {
    if (!a.message || a.read != now) continue;
    const auto from = where(d.modules[size_t(a.from_column)]), to = where(d.modules[size_t(a.to_column)]);
    if (from && to) arrow(draw, *from, *to, kMessage, 2.5f, 9);
  }
}

}  // namespace dw::view
