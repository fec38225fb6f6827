// The debugger's Module panel (the selected module: the interventions on it, its variables now and
// a step before, a plot of one over the steps, its neighbours and matches) with the session's
// files, the Statistics panel (per watchpoint, the paper's Fig. 7 live) and
// the help window.
#include <imgui.h>

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>

#include "app/view/debugger.h"
#include "app/view/widgets.h"

namespace dw::view {

void Debugger::inspector_panel() {
  place(panels_.module);
  ImGui::Begin("Module");
  const sim::Model& m = session_.model();
  if (!readout_.inspector) {
    ImGui::TextDisabled("click a module in the 3D view, a match or a neighbour");
    ImGui::End();
    return;
  }
  const Inspector& in = *readout_.inspector;
  ImGui::Text("module %u at step %" PRId64 "%s", m.universe.id(in.module), readout_.at.current,
              in.present ? "" : "  (absent)");
  // Which pose it is: the one after the step's physics (the 3D view's); the neighbours were
  // measured from the poses at the end of the step before (docs/design.md §2).
  if (in.pose) {
    const auto& p = in.pose->position;
    ImGui::SameLine();
    ImGui::TextDisabled("  after the step at (%.2f, %.2f, %.2f)", p[0], p[1], p[2]);
  }
  // The neighbours beside the module's name when they fit (click one to select it): at the panel's
  // top, never the line the fold cuts in half (at 1600x1000 they were, under the Statistics header).
  const char* neighbours = in.pose ? "neighbours (touching at the end of the step before):" : "neighbours:";
  flow(ImGui::CalcTextSize(neighbours).x);
  ImGui::TextDisabled("%s", neighbours);
  for (sim::ModuleId n : in.neighbors) {
    const std::string id = std::to_string(m.universe.id(n));
    flow(ImGui::CalcTextSize(id.c_str()).x + 2 * ImGui::GetStyle().FramePadding.x);
    if (ImGui::SmallButton(id.c_str())) {
      model_.on_module_click(n);
      readout_stale_ = true;
    }
    note_widget("neighbour " + id);
  }
  interventions_row(in);
  session_files_row();
  variables_table(in);
  if (!in.plot.empty()) {
    const std::string title = m.universe.variables[size_t(in.plot_column)] + " over steps " +
                              std::to_string(in.plot_from) + " to " +
                              std::to_string(in.plot_from + int64_t(in.plot.size()) - 1);
    // As tall as the panel has room for, its steps' line included (at 1600x1000 "step 0" was cut
    // in half by the panel's edge), between 40 and 70 pixels, and so that the fold falls between
    // two lines after it: the window's bottom padding shows what reaches into it, and the line
    // after the plot showed its top half there.
    const float line = ImGui::GetTextLineHeightWithSpacing();
    const float room = ImGui::GetContentRegionAvail().y - line - ImGui::GetTextLineHeight() -
                       ImGui::GetStyle().ItemSpacing.y + ImGui::GetStyle().WindowPadding.y;
    const float whole_lines_after = room > 70 ? std::ceil((room - 70) / line) : 0;
    // Before the title, on its line: the plotted variable's nearest change before and after this
    // step (the session's `find prev|next M VAR`), a reverse search through the history.
    const std::string& plotted = m.universe.variables[size_t(in.plot_column)];
    for (const bool back : {true, false}) {
      if (button(std::string(back ? "<" : ">") + "##change", true))
        apply({command::find_change(in.module, plotted, back)});
      if (ImGui::IsItemHovered())
        ImGui::SetTooltip("the nearest step %s this one where %s changed", back ? "before" : "after", plotted.c_str());
      ImGui::SameLine();
    }
    std::vector<PlotSeries> lines{{in.plot_label, in.plot}};
    for (size_t i = 0; i < in.plot_group.size(); ++i)
      lines.push_back(
          {in.plot_group[i].label, in.plot_group[i].values, kPlotOverlayColors[i % kPlotOverlayColors.size()]});
    const PlotDrawn drawn = history_plot(title, lines, in.plot_from, readout_.at.current,
                                         std::clamp(room - whole_lines_after * line, 40.0f, 70.0f));
    plot_rects_.push_back(drawn.area);
    plot_labels_.insert(plot_labels_.end(), drawn.labels.begin(), drawn.labels.end());
  }
  // The module's matches, one row each (which, its step, its slots), so that two of one step read
  // apart; a click goes to the match as a row of the matches table does.
  ImGui::Text("in %zu matches%s", in.matches_total, in.matches_total > in.matches.size() ? " (the first below)" : "");
  for (size_t i = 0; i < in.matches.size() && i < 8; ++i) {
    const MatchRef r = in.matches[i].ref;
    const std::string label = in.matches[i].watch + "  t=" + std::to_string(in.matches[i].t) + "  " +
                              in.matches[i].slots + "##match" + std::to_string(i);
    if (ImGui::Selectable(label.c_str(), model_.selected_match && *model_.selected_match == r)) {
      std::vector<std::string> commands;
      worker_->try_read([&](sim::Session& s) { commands = model_.on_match_click(s, r); });
      apply(commands);
      readout_stale_ = true;
    }
  }
  ImGui::End();
}

// The interventions on the selected module, at the top of its panel so that Set and Remove stay in
// sight however many variables, matches and neighbours it lists.
void Debugger::interventions_row(const Inspector& in) {
  const sim::Model& m = session_.model();
  set_column_ = std::clamp(set_column_, 0, int(m.variable_count()) - 1);
  std::vector<const char*> variables;
  for (const std::string& v : m.universe.variables) variables.push_back(v.c_str());
  choice("variable", set_column_, variables);
  ImGui::SameLine();
  ImGui::SetNextItemWidth(std::max(120.0f, ImGui::CalcTextSize("-9223372036854775808").x + 8));
  ImGui::InputScalar("##value", ImGuiDataType_S64, &set_value_);
  note_widget("value");
  ImGui::SameLine();
  if (button("Set")) apply({command::set(in.module, m.universe.variables[size_t(set_column_)], set_value_)});

  flow(button_width("Remove module"));
  if (button("Remove module")) apply({command::remove(in.module)});
  if (in.pose) {  // a physical world
    flow(160 + ImGui::GetStyle().ItemInnerSpacing.x + ImGui::CalcTextSize("impulse").x);
    ImGui::SetNextItemWidth(160);
    ImGui::InputFloat3("impulse", push_);
    flow(button_width("Push"));
    if (button("Push")) apply({command::push(in.module, {push_[0], push_[1], push_[2]})});
  }
  // How many there are, beside the buttons when there is room (not a line of its own).
  const size_t n = readout_.interventions.size();
  const std::string count = std::to_string(n) + (n == 1 ? " intervention" : " interventions") + " on this branch";
  if (ImGui::GetItemRectMax().x + ImGui::GetStyle().ItemSpacing.x + ImGui::CalcTextSize(count.c_str()).x <=
      ImGui::GetWindowPos().x + ImGui::GetWindowContentRegionMax().x) {
    ImGui::SameLine();
    ImGui::TextDisabled("%s", count.c_str());
  } else if (ImGui::IsItemHovered()) {
    ImGui::SetTooltip("%s", count.c_str());
  }
}

// The session's files: `save` (its watchpoints and this branch's interventions, through the same
// checks as every output; an existing file is replaced only once confirmed) and `record`. Under
// the interventions, in sight whatever the Module panel lists below.
void Debugger::session_files_row() {
  // A file's field as wide as its name (whole: "leader_election-branch." was cut at 1024 pixels),
  // its button beside it when both fit, else on the next line.
  auto file_field = [this](const char* id, char* path, size_t size, const std::string& name, const char* action) {
    const ImGuiStyle& style = ImGui::GetStyle();
    const float text = ImGui::CalcTextSize(path).x + 2 * style.FramePadding.x;
    const float avail = ImGui::GetContentRegionAvail().x;
    const float beside = avail - style.ItemSpacing.x - button_width(action);
    ImGui::SetNextItemWidth(std::min(std::max(120.0f, text + 4), text + 4 <= beside ? beside : avail));
    const bool edited = ImGui::InputText(id, path, size);
    note_widget(name, text);
    flow(button_width(action));
    return edited;
  };
  if (file_field("##save", save_path_, sizeof save_path_, "scenario-file", "save as scenario")) save_refused_.clear();
  if (button("save as scenario", true)) {
    save_refused_.clear();
    save_sent_ = save_path_;
    apply({command::save(save_path_, false)});
  }
  if (!save_refused_.empty() && save_refused_ == save_path_) {
    flow(button_width("overwrite it"));
    if (button("overwrite it", true)) {
      apply({command::save(save_refused_, true)});
      save_refused_.clear();
    }
  }
  file_field("##record", record_path_, sizeof record_path_, "trace-file", "record trace");
  if (button("record trace", true)) apply({command::record(record_path_)});
}

// The module's variables, their values whole (a cut `_priority` read as another number, and two
// modules' priorities could not be compared): the value columns as wide as their widest value, and
// where the panel has no room for both beside the names, the step before's value under each value.
void Debugger::variables_table(const Inspector& in) {
  const ImVec4 kChanged(1, 0.8f, 0.2f, 1);
  const float pad = 2 * ImGui::GetStyle().CellPadding.x + 2;
  float names = header_width("variable"), values = header_width("value (* changed)"),
        befores = header_width("step before");
  for (const VariableRow& v : in.variables) {
    names = std::max(names, ImGui::CalcTextSize(v.name.c_str()).x);
    values = std::max(values, ImGui::CalcTextSize((std::to_string(v.value) + " *").c_str()).x);
    if (v.before) befores = std::max(befores, ImGui::CalcTextSize(std::to_string(*v.before).c_str()).x);
  }
  // Each row ends in a "why?" that asks the session the value's causal history (the Why panel).
  const float why = ImGui::CalcTextSize("why?").x + 2 * ImGui::GetStyle().FramePadding.x;
  const bool side_by_side = names + values + befores + why + 4 * pad <= ImGui::GetContentRegionAvail().x;
  if (!side_by_side)
    values = std::max({values, befores + ImGui::CalcTextSize("before ").x, header_width("value (* changed), before")});
  if (!ImGui::BeginTable("vars", side_by_side ? 4 : 3, ImGuiTableFlags_RowBg | ImGuiTableFlags_Borders)) return;
  ImGui::TableSetupColumn("variable", ImGuiTableColumnFlags_WidthStretch);
  ImGui::TableSetupColumn(side_by_side ? "value (* changed)" : "value (* changed), before",
                          ImGuiTableColumnFlags_WidthFixed, values);
  if (side_by_side) ImGui::TableSetupColumn("step before", ImGuiTableColumnFlags_WidthFixed, befores);
  ImGui::TableSetupColumn("", ImGuiTableColumnFlags_WidthFixed, why);
  headers_row("variables");
  for (const VariableRow& v : in.variables) {
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    if (ImGui::Selectable(v.name.c_str(),
                          v.name == model_.plot_variable || (model_.plot_variable.empty() && &v == &in.variables[0])))
      model_.plot_variable = v.name, readout_stale_ = true;
    note_widget("plot " + v.name, 0, true);
    ImGui::TableNextColumn();
    if (v.changed()) label_cell(std::to_string(v.value) + " *", kChanged);
    else label_cell(std::to_string(v.value));
    if (!side_by_side) ImGui::TextDisabled("before %s", v.before ? std::to_string(*v.before).c_str() : "-");
    if (side_by_side) {
      ImGui::TableNextColumn();
      if (v.before) label_cell(std::to_string(*v.before));
      else ImGui::TextDisabled("-");
    }
    ImGui::TableNextColumn();
    if (button("why?##" + v.name, true))
      ask_why("why " + std::to_string(in.module) + " " + v.name + " " + std::to_string(readout_.at.current));
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("Why %s is %" PRId64 ": its causal history, as a space-time diagram (Y: the last changed)",
                        v.name.c_str(), v.value);
  }
  ImGui::EndTable();
}

// The panel under the Module panel, in tabs: the watchpoints' statistics, the selected match's
// group (group_panel.cpp), the bookmarks and a diff of two steps (marks_panel.cpp).
void Debugger::statistics_panel() {
  place(panels_.statistics);
  ImGui::Begin("Statistics");
  if (ImGui::BeginTabBar("below")) {
    // The frame's time in the tab's name: a line of its own pushed the plots out of a low panel.
    char statistics_label[64];
    std::snprintf(statistics_label, sizeof statistics_label, "statistics, frame %.1f ms###statistics",
                  double(shown_frame_ms_));
    const bool statistics = ImGui::BeginTabItem(statistics_label);
    note_widget("tab statistics");
    tall_tabs_ = !statistics;
    if (statistics) {
      statistics_tab();
      ImGui::EndTabItem();
    }
    // Named by the group it shows, so that it is seen without opening it.
    std::string label = "group";
    if (readout_.group)
      for (size_t i = 0; i < readout_.group->slots.size(); ++i)
        label += " " + readout_.group->slots[i] + "=" +
                 std::to_string(session_.model().universe.id(readout_.group->modules[i]));
    const bool group = ImGui::BeginTabItem((label + "###group").c_str());
    note_widget("tab group");
    if (group) {
      group_tab();
      ImGui::EndTabItem();
    }
    const bool marks = ImGui::BeginTabItem("marks");
    note_widget("tab marks");
    if (marks) {
      marks_tab();
      ImGui::EndTabItem();
    }
    const bool diff = ImGui::BeginTabItem("diff");
    note_widget("tab diff");
    if (diff) {
      diff_tab();
      ImGui::EndTabItem();
    }
    ImGui::EndTabBar();
  }
  ImGui::End();
}

void Debugger::statistics_tab() {
  for (size_t w = 0; w < readout_.stats.size(); ++w) {
    const std::vector<StatsRow>& rows = readout_.stats[w];
    if (!ImGui::CollapsingHeader(readout_.watches[w].spec.name.c_str(), ImGuiTreeNodeFlags_DefaultOpen)) continue;
    if (rows.empty()) {
      ImGui::TextDisabled("no steps yet");
      continue;
    }
    const StatsRow& last = rows.back();
    // A step's time in the unit that shows it ("0.000 ms" was most steps).
    auto duration = [](double seconds) {
      char text[32];
      if (seconds < 1e-3) std::snprintf(text, sizeof text, "%.0f \u00b5s", seconds * 1e6);
      else std::snprintf(text, sizeof text, "%.2f ms", seconds * 1e3);
      return std::string(text);
    };
    ImGui::TextWrapped("step %" PRId64 ": %" PRIu64 " PatternMatchers live, %" PRIu64 " created, %" PRIu64
                       " messages, %s",
                       last.step, last.live, last.created, last.messages, duration(last.seconds).c_str());
    std::vector<float> live, created, messages, us;
    for (const StatsRow& r : rows) {
      live.push_back(float(r.live));
      created.push_back(float(r.created));
      messages.push_back(float(r.messages));
      us.push_back(float(r.seconds * 1e6));
    }
    ImGui::PushID(int(w));
    // Five small plots over the steps up to the current one, side by side: each from 0 (its bottom)
    // to its largest value, written in it (they had no values at all).
    if (ImGui::BeginTable("plots", 5, ImGuiTableFlags_SizingStretchSame)) {
      auto plot = [this](const char* what, const std::vector<float>& values, bool histogram = false) {
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(what);
        const std::string id = std::string("##") + what;
        const float top = values.empty() ? 0 : std::max(1.0f, *std::max_element(values.begin(), values.end()));
        char most[32];
        std::snprintf(most, sizeof most, "max %.0f", double(top));
        ImGui::SetNextItemWidth(-FLT_MIN);  // the cell's width (see the Module panel's plot)
        if (histogram)
          ImGui::PlotHistogram(id.c_str(), values.data(), int(values.size()), 0, most, 0, top, ImVec2(0, 32));
        else ImGui::PlotLines(id.c_str(), values.data(), int(values.size()), 0, most, 0, top, ImVec2(0, 32));
        plot_rects_.push_back({ImGui::GetItemRectMin().x, ImGui::GetItemRectMin().y, ImGui::GetItemRectMax().x,
                               ImGui::GetItemRectMax().y});
      };
      plot("live", live);
      plot("created", created);
      plot("messages", messages);
      plot("step \u00b5s", us);
      // The paper's Fig. 7: PatternMatchers by slots filled (0..k), at this step.
      plot("by filled", std::vector<float>(last.live_by_filled.begin(), last.live_by_filled.end()), true);
      ImGui::EndTable();
    }
    ImGui::PopID();
  }
}

void Debugger::help_window() {
  ImGui::SetNextWindowPos(ImGui::GetMainViewport()->GetCenter(), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
  ImGui::Begin("Help (F1)", &model_.show_help, ImGuiWindowFlags_AlwaysAutoResize);
  if (ImGui::BeginTable("keys", 2, ImGuiTableFlags_RowBg)) {
    for (const KeyHelp& k : key_help()) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(k.keys.data(), k.keys.data() + k.keys.size());
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(k.what.data(), k.what.data() + k.what.size());
    }
    ImGui::EndTable();
  }
  ImGui::TextDisabled("A timeline lane per watchpoint shows where it matched; the bottom lane, interventions.");
  ImGui::End();
}

}  // namespace dw::view
