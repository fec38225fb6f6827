// The timeline under the transport bar: a lane per watchpoint marking (by density) the steps it
// matched, the interventions' lane, the bookmarks' flags, the cursor, and the steps written under
// it; a click or drag seeks, the wheel zooms, a right drag pans.
#include <imgui.h>

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <tuple>

#include "app/view/debugger.h"
#include "app/view/widgets.h"

namespace dw::view {

void Debugger::timeline(float width) {
  // One lane a watchpoint, then the interventions' lane; the cursor across all.
  // The lanes' names whole, up to 30% of the width (cut with "..." beyond).
  std::vector<std::string> names{"interventions"};
  for (const WatchRow& row : readout_.watches) names.push_back(row.spec.name);
  const float lane = 14, label = names_width(names, 100, std::max(100.0f, width * 0.3f));
  const size_t lanes = readout_.watches.size() + 1;
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  const float lanes_height = lane * float(lanes) + 4;
  std::tie(timeline_.first, timeline_.last) = model_.timeline_range.shown(readout_.at);
  timeline_y_ = origin.y;
  timeline_height_ = lanes_height;
  timeline_.x0 = origin.x + label;
  timeline_.width = std::max(10.0f, width - label - 4);
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const int columns = int(timeline_.width);
  const float simulated = std::clamp(
      timeline_.x_of(readout_.at.latest) + 0.5f * timeline_.width / float(timeline_.last - timeline_.first + 1),
      timeline_.x0, timeline_.x0 + timeline_.width);
  draw->AddRectFilled(ImVec2(timeline_.x0, origin.y), ImVec2(timeline_.x0 + timeline_.width, origin.y + lanes_height),
                      IM_COL32(45, 45, 50, 255));
  if (readout_.at.latest >= timeline_.first)
    draw->AddRectFilled(ImVec2(timeline_.x0, origin.y), ImVec2(simulated, origin.y + lanes_height),
                        IM_COL32(60, 62, 70, 255));
  const float scale_y = origin.y + lanes_height;
  timeline_scale(scale_y);
  // The lanes were counted for the timeline as drawn last; a new width or length asks for a fresh Readout.
  timeline_columns_ = columns;
  if (readout_.columns != columns || readout_.timeline.last != timeline_.last ||
      readout_.timeline.width != timeline_.width)
    readout_stale_ = true;
  const std::vector<uint32_t> interventions_lane = lane_density(readout_.intervention_steps, timeline_, columns);
  const float mark = std::max(1.0f, std::floor(timeline_.width / float(timeline_.last - timeline_.first + 1)) - 2);
  for (size_t w = 0; w < lanes; ++w) {
    const float y = origin.y + lane * float(w) + 2;
    const bool interventions = w == readout_.watches.size();
    const ImU32 color = interventions ? IM_COL32(240, 240, 240, 255) : lane_color(w);
    const std::string& name = interventions ? names.front() : readout_.watches[w].spec.name;
    const std::string shown = fitted_text(name, label - 6);
    if (shown != name) drawing_cut_labels_.push_back(name);
    draw->AddText(ImVec2(origin.x, y - 2), color, shown.c_str());
    const std::vector<uint32_t>& density = interventions ? interventions_lane : readout_.watches[w].lane;
    if (density.size() != size_t(columns)) continue;  // counted for another width: the next Readout's
    const uint32_t most = density.empty() ? 0 : *std::max_element(density.begin(), density.end());
    for (int c = 0; c < columns; ++c) {
      if (!density[size_t(c)]) continue;
      // Density: a column's height grows with the log of its matches, so one match still shows.
      const float share =
          most <= 1 ? 1.0f : 0.35f + 0.65f * std::log1p(float(density[size_t(c)])) / std::log1p(float(most));
      // As wide as its step when zoomed in (less a gap), so that the cursor line never hides it.
      const float x = timeline_.x0 + float(c) + 0.5f;
      draw->AddRectFilled(ImVec2(x - mark / 2, y + lane - 2 - (lane - 3) * share), ImVec2(x + mark / 2, y + lane - 2),
                          color);
    }
  }
  const int64_t current = std::max<int64_t>(0, readout_.at.current);
  if (current >= timeline_.first && current <= timeline_.last) {
    const float cx = timeline_.x_of(current);
    draw->AddLine(ImVec2(cx, origin.y), ImVec2(cx, origin.y + lanes_height), IM_COL32(255, 255, 255, 255), 2);
  }
  const sim::Bookmark* hovered_mark = timeline_bookmarks(origin.y, lanes_height);

  ImGui::SetCursorScreenPos(ImVec2(timeline_.x0, origin.y));
  ImGui::InvisibleButton("timeline", ImVec2(timeline_.width, lanes_height));
  const ImGuiIO& io = ImGui::GetIO();
  const float mouse_x = io.MousePos.x;
  if (ImGui::IsItemHovered()) {
    if (hovered_mark)
      ImGui::SetTooltip("bookmark at step %" PRId64 ": %s", hovered_mark->at,
                        hovered_mark->note.empty() ? "(no note)" : hovered_mark->note.c_str());
    else
      ImGui::SetTooltip("step %" PRId64 " (click or drag to go there; wheel: zoom, right drag: pan)",
                        timeline_.step_at(mouse_x));
    if (io.MouseWheel != 0)
      model_.timeline_range.zoom(std::pow(0.8, double(io.MouseWheel)), timeline_.step_at(mouse_x), readout_.at);
    if (ImGui::IsMouseDragging(ImGuiMouseButton_Right)) {
      const float steps_per_pixel = float(timeline_.last - timeline_.first + 1) / timeline_.width;
      const auto steps = int64_t(-ImGui::GetMouseDragDelta(ImGuiMouseButton_Right).x * steps_per_pixel);
      if (steps != 0) {
        model_.timeline_range.pan(steps, readout_.at);
        ImGui::ResetMouseDragDelta(ImGuiMouseButton_Right);
      }
    }
  }
  // A click seeks; a drag seeks as it goes, once the session is free (never queueing a backlog).
  if (ImGui::IsItemActive() &&
      (ImGui::IsItemClicked() || (worker_->idle() && timeline_.step_at(mouse_x) != readout_.at.current)))
    apply(model_.on_timeline_click(timeline_, mouse_x, readout_.at));
  ImGui::SetCursorScreenPos(ImVec2(origin.x, scale_y));
  if (model_.timeline_range.fitted) {
    ImGui::Dummy(ImVec2(1, ImGui::GetTextLineHeight()));
  } else {
    if (button("fit", true)) model_.timeline_range.fit();
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Show step 0 to the latest again, following the run");
  }
}

// The steps under the timeline: the cursor's in white under its line (or at the edge it lies
// beyond, with an arrow, when zoomed away from it), the range's first and last, and round steps
// between them about every 100 pixels, each written where it does not run into another.
void Debugger::timeline_scale(float y) {
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const float left = timeline_.x0, right = timeline_.x0 + timeline_.width, gap = ImGui::CalcTextSize("  ").x;
  std::vector<std::pair<float, float>> taken;  // the spans written so far
  auto write = [&](const std::string& text, float centre, ImU32 color) {
    const float w = ImGui::CalcTextSize(text.c_str()).x;
    const float x = std::clamp(centre - w / 2, left, right - w);
    for (const auto& [a, b] : taken)
      if (x < b + gap && x + w > a - gap) return;
    taken.emplace_back(x, x + w);
    draw->AddText(ImVec2(x, y), color, text.c_str());
  };
  const int64_t current = std::max<int64_t>(0, readout_.at.current);
  const ImU32 white = IM_COL32(255, 255, 255, 255), grey = IM_COL32(170, 170, 170, 255);
  if (current < timeline_.first) write("< " + std::to_string(current), left, white);
  else if (current > timeline_.last) write(std::to_string(current) + " >", right, white);
  else write(std::to_string(current), timeline_.x_of(current), white);
  write(std::to_string(timeline_.first), left, grey);
  write(std::to_string(timeline_.last), right, grey);
  // A round step interval (1, 2 or 5 times a power of ten) about 100 pixels apart.
  const double per_pixel = double(timeline_.last - timeline_.first + 1) / std::max(1.0f, timeline_.width);
  const int64_t round[3] = {1, 2, 5};
  int64_t power = 1;
  size_t k = 0;
  while (double(round[k] * power) < per_pixel * 100)
    if (++k == 3) k = 0, power *= 10;
  const int64_t every = round[k] * power;
  for (int64_t t = (timeline_.first / every + 1) * every; t < timeline_.last; t += every) {
    const float x = timeline_.x_of(t);
    draw->AddLine(ImVec2(x, y - 3), ImVec2(x, y), grey);
    write(std::to_string(t), x, grey);
  }
}

}  // namespace dw::view
