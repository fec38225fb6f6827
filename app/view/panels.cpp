// The debugger's panels (Dear ImGui): transport, watchpoints and the editor, the matches table (the
// timeline is in timeline.cpp; the Module, Statistics and help panels in module_panels.cpp). Each draws from
// the Readout and sends session commands; none reads the session while a job may run.
#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <optional>
#include <sstream>
#include <tuple>

#include "app/view/debugger.h"
#include "app/view/widgets.h"
#include "shell/command.h"
#include "shell/output_files.h"
#include "sim/unknown_variables.h"
#include "watch/explain.h"
#include "watch/watchpoint.h"

namespace dw::view {

void Debugger::draw_panels() {
  plot_rects_.clear();
  plot_labels_.clear();
  transport_panel();
  watchpoints_panel();
  matches_panel();
  inspector_panel();
  statistics_panel();
  why_panel();
}

void Debugger::transport_panel() {
  place(panels_.transport);
  ImGui::Begin("Transport and timeline", nullptr, ImGuiWindowFlags_NoCollapse);
  if (panels_.too_small) {
    const ImGuiViewport* vp = ImGui::GetMainViewport();
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.35f, 0.3f, 1.0f));  // wrapped: it was cut
    ImGui::TextWrapped("The window is %.0fx%.0f: the panels need %.0fx%.0f or more to show whole. Enlarge it.",
                       vp->WorkSize.x, vp->WorkSize.y, PanelLayout::kMinWidth, PanelLayout::kMinHeight);
    ImGui::PopStyleColor();
  }
  const Position& at = readout_.at;
  if (button(model_.playing ? "Pause (Space)" : "Play (Space)")) press(Key::Space);
  for (const char* label : {"< Back", "Step >", "Run"}) {
    flow(button_width(label));
    if (button(label))
      label[0] == '<' ? press(Key::Left) : label[0] == 'S' ? press(Key::Right) : apply({command::run()});
  }
  if (!scenario_.scripts.empty()) {
    flow(button_width("Reload scripts"));
    if (button("Reload scripts")) apply({command::reload()});
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("Load the scenario's Lua scripts again: they run from the step after this one, a new branch");
  }
  const float slider = 150 + ImGui::GetStyle().ItemInnerSpacing.x + ImGui::CalcTextSize("steps/s").x;
  flow(slider);
  ImGui::SetNextItemWidth(150);
  ImGui::SliderInt("steps/s", &model_.speed, 0, 240, model_.speed == 0 ? "fastest" : "%d");
  flow(110 + ImGui::GetStyle().ItemSpacing.x + button_width("Go to step"));
  ImGui::SetNextItemWidth(110);
  ImGui::InputInt("##goto", &goto_step_);
  note_widget("goto");
  ImGui::SameLine();
  if (button("Go to step")) {
    model_.playing = false;
    const int64_t t = std::max(0, goto_step_);
    apply({t <= at.latest ? command::seek(t) : command::run_to(t)});
  }
  flow(button_width("< Prev match (P)"));
  if (button("< Prev match (P)")) press(Key::P);
  flow(button_width("Next match (N) >"));
  if (button("Next match (N) >")) press(Key::N);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("The chosen watchpoint's next match: simulated on to it when none is known yet");
  flow(140);
  ImGui::SetNextItemWidth(140);
  const char* chosen = size_t(model_.chosen_watch) < readout_.watches.size()
                           ? readout_.watches[size_t(model_.chosen_watch)].spec.name.c_str()
                           : "(none)";
  if (ImGui::BeginCombo("##chosen", chosen)) {
    for (size_t w = 0; w < readout_.watches.size(); ++w)
      if (ImGui::Selectable(readout_.watches[w].spec.name.c_str(), int(w) == model_.chosen_watch))
        model_.chosen_watch = int(w);
    ImGui::EndCombo();
  }

  if (at.latest < 0)  // nothing simulated yet: no step to speak of
    ImGui::Text("no step simulated yet (the scenario runs %" PRId64 ")", at.end);
  else {
    // Said as the status line says it; a step not yet decided by every watchpoint (after an
    // intervention, while the session simulates ahead) says so rather than "decided through -1".
    const std::string decided = readout_.decided >= at.current
                                    ? "decided through " + std::to_string(readout_.decided)
                                    : std::string("this step not yet decided by every watchpoint");
    ImGui::TextWrapped("%s, %s; the scenario runs %" PRId64 "   history: %s every %" PRId64 " steps, %.1f MiB",
                       position_words(at.current, at.latest).c_str(), decided.c_str(), at.end,
                       counted(int64_t(readout_.keyframes), "keyframe").c_str(), readout_.keyframe_interval,
                       double(readout_.history_bytes) / (1 << 20));
  }
  if (!worker_->idle()) {
    const auto [done, total] = worker_->progress();
    ImGui::ProgressBar(total > 0 ? float(done) / float(total) : 0.0f, ImVec2(300, 0),
                       total > 0 ? (std::to_string(done) + " / " + std::to_string(total)).c_str() : "working");
    ImGui::SameLine();
    if (button("Cancel (Esc)")) worker_->cancel();
    ImGui::SameLine();
  }
  if (readout_.failure) {
    // What stopped the run, in red, at the step it happened; the module is selected.
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.35f, 0.3f, 1.0f));
    ImGui::TextWrapped("Program error at step %" PRId64 " (module %" PRId64 "); the run stands at step %" PRId64 ": %s",
                       readout_.failure->step, int64_t(scenario_.model->universe.id(readout_.failure->module)),
                       at.latest, readout_.failure->message.c_str());
    ImGui::PopStyleColor();
  } else if (status_failed_) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.35f, 0.3f, 1.0f));
    ImGui::TextWrapped("%s", status_.c_str());
    ImGui::PopStyleColor();
  } else {
    ImGui::TextWrapped("%s", status_.c_str());
  }
  // A pause watchpoint that matches at every step would stop each Run a step further: the ways on.
  if (!paused_on_.empty()) {
    if (button("Continue")) apply({command::continue_run()});
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Run on past this pause, to the next one or the end");
    ImGui::SameLine();
    if (button("Stop pausing on " + paused_on_))
      apply({command::action(paused_on_, sim::MatchAction::Log), command::continue_run()});
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("%s logs its matches from now on (nothing is evaluated again), and the run goes on",
                        paused_on_.c_str());
  }
  timeline(ImGui::GetContentRegionAvail().x);
  ImGui::End();
}

namespace {

// How a watchpoint reads the run: "distributed chain", "distributed ordered simultaneous".
std::string reading_of(const WatchRow& row) {
  const bool simultaneous = row.spec.distributed() && row.spec.options.states == watch::States::Simultaneous;
  return std::string(row.spec.algorithm_name()) + " " + std::string(row.spec.shape_name()) +
         (simultaneous ? " simultaneous" : "");
}

}  // namespace

void Debugger::watchpoints_panel() {
  place(panels_.watchpoints);
  ImGui::Begin("Watchpoints");
  // Names, action, count, buttons and headers whole ("matc..." was cut); the reading takes what is
  // left, cut visibly. In a narrow panel the reading, then the action, go into the name's tooltip.
  std::vector<std::string> names{"name"}, actions{"action"}, counts{"matches"}, readings;
  for (const WatchRow& row : readout_.watches) {
    names.push_back(row.spec.name);
    actions.push_back(std::string(sim::action_name(row.spec.action)));
    counts.push_back(std::to_string(row.matches));
    readings.push_back(reading_of(row));
  }
  for (const DisabledWatch& d : disabled_) names.push_back(d.name);
  const ImGuiStyle& style = ImGui::GetStyle();
  const float avail = ImGui::GetContentRegionAvail().x;
  const float buttons =
      ImGui::CalcTextSize("edit").x + ImGui::CalcTextSize("remove").x + 4 * style.FramePadding.x + style.ItemSpacing.x;
  const float name_width = names_width(names, 40, avail * 0.45f), action_width = names_width(actions, 0, 1e9f),
              count_width = names_width(counts, 0, 1e9f);
  // The columns that always show (their widths hold their padding; the table's borders besides),
  // then the action and the reading while there is room for them.
  const float pad = 2 * style.CellPadding.x,
              kept = ImGui::GetFrameHeight() + pad + name_width + count_width + buttons + pad + 6 * style.CellPadding.x;
  const bool action_shown = avail - kept >= action_width;
  const bool reading_shown = action_shown && avail - kept - action_width >= header_width("reading") + pad;
  if (ImGui::BeginTable("watches", 4 + int(action_shown) + int(reading_shown),
                        ImGuiTableFlags_RowBg | ImGuiTableFlags_Borders | ImGuiTableFlags_SizingFixedFit)) {
    ImGui::TableSetupColumn("on", ImGuiTableColumnFlags_WidthFixed, ImGui::GetFrameHeight());
    ImGui::TableSetupColumn("name", ImGuiTableColumnFlags_WidthFixed, name_width - pad);
    if (reading_shown) ImGui::TableSetupColumn("reading", ImGuiTableColumnFlags_WidthStretch);
    if (action_shown) ImGui::TableSetupColumn("action", ImGuiTableColumnFlags_WidthFixed, action_width - pad);
    ImGui::TableSetupColumn("matches", ImGuiTableColumnFlags_WidthFixed, count_width - 2 * style.CellPadding.x);
    ImGui::TableSetupColumn("", ImGuiTableColumnFlags_WidthFixed, buttons);
    headers_row("watchpoints");
    for (size_t w = 0; w < readout_.watches.size(); ++w) {
      const WatchRow& row = readout_.watches[w];
      ImGui::PushID(int(w));
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      bool on = true;
      if (ImGui::Checkbox("##on", &on)) {  // off: out of the session, its definition kept here
        disabled_.push_back({row.spec.name, row.spec.words(), row.spec.text});
        apply({command::unwatch(row.spec.name)});
      }
      ImGui::TableNextColumn();
      label_cell(row.spec.name, ImColor(lane_color(w)));
      if (ImGui::IsItemHovered())
        ImGui::SetTooltip("%s\n%s, %s, lag %" PRId64 " steps", row.spec.text.c_str(), readings[w].c_str(),
                          actions[w + 1].c_str(), row.lag);
      const bool simultaneous = row.spec.distributed() && row.spec.options.states == watch::States::Simultaneous;
      if (reading_shown) {
        ImGui::TableNextColumn();
        cell_text(readings[w]);
      }
      if (action_shown) {
        ImGui::TableNextColumn();
        cell_text(std::string(sim::action_name(row.spec.action)));
      }
      ImGui::TableNextColumn();
      cell_text(std::to_string(row.matches));
      ImGui::TableNextColumn();
      if (button("edit##" + row.spec.name, true)) {
        edit_name_ = row.spec.name;
        edit_text_ = row.spec.text;
        edit_algorithm_ = row.spec.distributed() ? 1 : 0;
        const std::string_view shape = row.spec.shape_name();
        edit_shape_ = shape == "chain" ? 0 : shape == "ordered" ? 1 : 2;
        edit_states_ = simultaneous ? 1 : 0;
        edit_action_ = row.spec.action == sim::MatchAction::Pause   ? 1
                       : row.spec.action == sim::MatchAction::Count ? 2
                                                                    : 0;
        edit_checked_.clear();
      }
      ImGui::SameLine();
      if (button("remove##" + row.spec.name, true)) apply({command::unwatch(row.spec.name)});
      ImGui::PopID();
    }
    for (size_t d = 0; d < disabled_.size(); ++d) {
      ImGui::PushID(int(1000 + d));
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      bool on = false;
      if (ImGui::Checkbox("##on", &on)) {  // on again: evaluated over the whole history
        apply({command::watch(disabled_[d].name, disabled_[d].options, disabled_[d].text)});
        disabled_.erase(disabled_.begin() + std::ptrdiff_t(d));
        ImGui::PopID();
        break;
      }
      ImGui::TableNextColumn();
      ImGui::TextDisabled("%s", disabled_[d].name.c_str());
      ImGui::TableNextColumn();
      ImGui::TextDisabled("off");
      ImGui::PopID();
    }
    ImGui::EndTable();
  }
  editor();
  ImGui::End();
}

void Debugger::editor() {
  ImGui::Separator();
  ImGui::TextWrapped("Editor: compiled as you type; Add / Replace evaluates it over the whole history");
  static const char* kAlgorithms[] = {"centralized", "distributed"};
  static const char* kShapes[] = {"chain", "ordered", "any"};
  static const char* kStates[] = {"consistent", "simultaneous"};
  static const char* kActions[] = {"log", "pause", "count"};
  ImGui::SetNextItemWidth(120);
  ImGui::InputText("name", &edit_name_);
  note_widget("name");
  // Each choice as wide as its widest word, so that none is cut ("lo" for log).
  choice("algorithm", edit_algorithm_, kAlgorithms);
  flow(combo_width_of(kShapes));
  choice("shape", edit_shape_, kShapes);
  if (edit_algorithm_ == 1) {
    flow(combo_width_of(kStates));
    choice("states", edit_states_, kStates);
  }
  flow(combo_width_of(kActions));
  choice("action", edit_action_, kActions);
  if (mono_font_) ImGui::PushFont(mono_font_);
  ImGui::InputTextMultiline("##text", &edit_text_, ImVec2(-1, ImGui::GetTextLineHeight() * 4));
  if (mono_font_) ImGui::PopFont();
  note_widget("text");

  // Compiled whenever the text changes, with the diagnostics the command line prints.
  const std::string key = edit_name_ + "\n" + edit_text_;
  if (key != edit_checked_) {
    edit_checked_ = key;
    edit_ok_ = false;
    edit_diagnostics_.clear();
    edit_explanation_.clear();
    if (!edit_text_.empty()) {
      auto compiled = watch::compile_watchpoint(edit_name_, watch::SourceText("<editor>", edit_text_));
      if (auto* error = std::get_if<watch::CompileError>(&compiled)) {
        edit_diagnostics_ = error->format();
      } else {
        const watch::Watchpoint& w = std::get<watch::Watchpoint>(compiled);
        const std::vector<watch::Diagnostic> unknown = sim::unknown_variable_mistakes(session_.model(), w);
        if (!unknown.empty()) {
          edit_diagnostics_ = watch::format_diagnostics(*w.source, unknown);
        } else {
          std::ostringstream explained;
          watch::explain_watchpoint(w, explained);
          edit_explanation_ = explained.str();
          edit_ok_ = true;
        }
      }
    }
  }
  // The reading chosen, sent as the session's `watch` words. One that cannot find the shape (the
  // paper's distributed one finds chains only) is said, not sent.
  sim::WatchSpec chosen;
  for (const char* word : {kAlgorithms[edit_algorithm_], kShapes[edit_shape_], kActions[edit_action_]})
    sim::read_word(chosen, word);
  if (chosen.distributed()) sim::read_word(chosen, kStates[edit_states_]);
  const std::string unsupported = watch::unsupported(chosen.algorithm, chosen.options);
  ImGui::BeginDisabled(!edit_ok_ || edit_name_.empty() || !unsupported.empty());
  const bool exists = std::any_of(readout_.watches.begin(), readout_.watches.end(),
                                  [&](const WatchRow& w) { return w.spec.name == edit_name_; });
  if (button(exists ? "Replace" : "Add")) apply({command::watch(edit_name_, chosen.words(), edit_text_)});
  ImGui::EndDisabled();
  if (!unsupported.empty()) {
    ImGui::SameLine();
    ImGui::TextDisabled("%s", unsupported.c_str());
  }
  if (!edit_diagnostics_.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, IM_COL32(255, 120, 110, 255));
    if (mono_font_) ImGui::PushFont(mono_font_);
    ImGui::TextUnformatted(edit_diagnostics_.c_str());
    if (mono_font_) ImGui::PopFont();
    ImGui::PopStyleColor();
  } else if (!edit_explanation_.empty()) {
    const bool open = ImGui::CollapsingHeader("what it means (dwatch check)");
    note_widget("what it means");  // a script's `press what it means`
    if (open) ImGui::TextUnformatted(edit_explanation_.c_str());
  }
}

void Debugger::matches_panel() {
  place(panels_.matches);
  ImGui::Begin("Matches");
  MatchFilter& filter = model_.filter;
  ImGui::SetNextItemWidth(120);
  const char* watch_label = filter.watch >= 0 && size_t(filter.watch) < readout_.watches.size()
                                ? readout_.watches[size_t(filter.watch)].spec.name.c_str()
                                : "every watch";
  const bool open = ImGui::BeginCombo("##filter_watch", watch_label);
  note_widget("match filter", combo_width(watch_label));  // `press match filter: W` once open
  if (open) {
    if (ImGui::Selectable("every watch", filter.watch < 0)) filter.watch = -1, readout_stale_ = true;
    note_widget("match filter: every watch", 0, true);
    for (size_t w = 0; w < readout_.watches.size(); ++w) {
      if (ImGui::Selectable(readout_.watches[w].spec.name.c_str(), int(w) == filter.watch))
        filter.watch = int(w), readout_stale_ = true;
      note_widget("match filter: " + readout_.watches[w].spec.name, 0, true);
    }
    ImGui::EndCombo();
  }
  flow(100 + ImGui::GetStyle().ItemInnerSpacing.x + ImGui::CalcTextSize("module (-1: any)").x);
  ImGui::SetNextItemWidth(100);
  const bool filtered = ImGui::InputInt("module (-1: any)", &filter_module_);
  if (filtered) {
    filter_module_ = std::max(-1, filter_module_);
    filter.module = filter_module_ >= 0 ? std::optional<sim::ModuleId>(sim::ModuleId(filter_module_)) : std::nullopt;
    readout_stale_ = true;
  }
  flow(button_width("copy JSON lines"));
  if (button("copy JSON lines", true)) {
    std::string lines;
    worker_->try_read([&](sim::Session&) {
      for (const MatchRowText& r : readout_.match_rows)
        lines += shell_.match_json(r.ref.watch, r.ref.index).dump() + "\n";
    });
    ImGui::SetClipboardText(lines.c_str());
    status("copied " + std::to_string(readout_.match_rows.size()) + " matches as JSON lines");
  }
  ImGui::SetNextItemWidth(width_beside({"save the matches"}));
  ImGui::InputText("##matches_path", matches_path_, sizeof matches_path_);
  note_widget("matches-file");
  ImGui::SameLine();
  if (button("save the matches", true)) save_matches();
  ImGui::Text("%zu matches%s", readout_.match_total,
              readout_.match_total > readout_.match_rows.size() ? " (the first shown: filter to narrow)" : "");
  std::vector<std::string> names{"watch"};
  for (const WatchRow& row : readout_.watches) names.push_back(row.spec.name);
  const float watch_width = names_width(names, header_width("watch", true), 200), why_width = button_width("why?");
  // The steps as wide as their header and its sort arrow (or the latest step, if wider).
  const float steps = std::max(header_width("detected", true),
                               ImGui::CalcTextSize(std::to_string(std::max<int64_t>(0, readout_.at.latest)).c_str()).x);
  // A "why?" per row (the match's causal history, in the Why panel) while the slots keep room for
  // their header and a group; in a narrow panel, one for the chosen match beside the count.
  const ImGuiStyle& style = ImGui::GetStyle();
  const float fixed = watch_width + std::max(header_width("t", true), steps * 0.7f) + steps + why_width +
                      10 * style.CellPadding.x + style.ScrollbarSize;
  const bool why_column =
      ImGui::GetContentRegionAvail().x - fixed >= header_width("slots") + ImGui::CalcTextSize("a=77 b=77 c=77").x;
  if (!why_column && model_.selected_match && model_.selected_match->watch < readout_.watches.size()) {
    flow(button_width("why? the chosen match"));
    if (button("why? the chosen match", true))
      ask_why("why match " + shell::command_word(readout_.watches[model_.selected_match->watch].spec.name) + " " +
              std::to_string(model_.selected_match->index));
  }
  const ImGuiTableFlags flags = ImGuiTableFlags_RowBg | ImGuiTableFlags_Borders | ImGuiTableFlags_ScrollY |
                                ImGuiTableFlags_Sortable | ImGuiTableFlags_SizingStretchProp;
  if (ImGui::BeginTable("matches", why_column ? 5 : 4, flags)) {
    ImGui::TableSetupScrollFreeze(0, 1);
    ImGui::TableSetupColumn("watch", ImGuiTableColumnFlags_WidthFixed, watch_width, 1);
    ImGui::TableSetupColumn("t", ImGuiTableColumnFlags_DefaultSort | ImGuiTableColumnFlags_WidthFixed,
                            std::max(header_width("t", true), steps * 0.7f), 0);
    ImGui::TableSetupColumn("detected", ImGuiTableColumnFlags_WidthFixed, steps, 2);
    ImGui::TableSetupColumn("slots", ImGuiTableColumnFlags_NoSort | ImGuiTableColumnFlags_WidthStretch, 1, 3);
    if (why_column)
      ImGui::TableSetupColumn("", ImGuiTableColumnFlags_NoSort | ImGuiTableColumnFlags_WidthFixed, why_width, 4);
    headers_row("matches");
    if (ImGuiTableSortSpecs* sort = ImGui::TableGetSortSpecs(); sort && sort->SpecsDirty && sort->SpecsCount > 0) {
      const ImGuiTableColumnSortSpecs& s = sort->Specs[0];
      filter.order = s.ColumnUserID == 1   ? MatchFilter::Order::Watch
                     : s.ColumnUserID == 2 ? MatchFilter::Order::Detected
                                           : MatchFilter::Order::Step;
      filter.descending = s.SortDirection == ImGuiSortDirection_Descending;
      sort->SpecsDirty = false;
      readout_stale_ = true;
    }
    ImGuiListClipper clipper;
    clipper.Begin(int(readout_.match_rows.size()));
    while (clipper.Step())
      for (int i = clipper.DisplayStart; i < clipper.DisplayEnd; ++i) {
        const MatchRowText& r = readout_.match_rows[size_t(i)];
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        const bool chosen = model_.selected_match == r.ref;
        // The row is the selectable; its watch name is drawn over it, whole or visibly cut.
        if (ImGui::Selectable(("##match" + std::to_string(i)).c_str(), chosen,
                              ImGuiSelectableFlags_SpanAllColumns | ImGuiSelectableFlags_AllowItemOverlap)) {
          std::vector<std::string> commands;
          worker_->try_read([&](sim::Session& s) { commands = model_.on_match_click(s, r.ref); });
          apply(commands);
          readout_stale_ = true;
        }
        ImGui::SameLine(0, 0);
        label_cell(r.watch);
        ImGui::TableNextColumn();
        ImGui::Text("%" PRId64, r.t);
        ImGui::TableNextColumn();
        ImGui::Text("%" PRId64, r.detected);
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(r.slots.c_str());
        if (!why_column) continue;
        ImGui::TableNextColumn();
        if (button("why?##match " + std::to_string(i), true))
          ask_why("why match " + shell::command_word(r.watch) + " " + std::to_string(r.ref.index));
      }
    ImGui::EndTable();
  }
  ImGui::End();
}

// Every match of every watchpoint to the matches' file, as the match log writes them
// (docs/design.md §5).
void Debugger::save_matches() {
  std::string lines;
  size_t written = 0;
  const bool read = worker_->try_read([&](sim::Session& s) {
    for (uint32_t w = 0; w < s.watches().size(); ++w)
      for (size_t i = 0; i < s.matches(w).size(); ++i, ++written) lines += shell_.match_json(w, i).dump() + "\n";
  });
  // As every output of dwatch: never over an input, and whole or not at all.
  std::unique_ptr<sim::OutputFile> out;
  std::string error = read ? shell::open_output_apart(scenario_.inputs, {"the matches' file", matches_path_}, out)
                           : "the session is busy: save again when it is done";
  if (error.empty()) {
    out->stream() << lines;
    error = out->commit();
  }
  if (error.empty()) status("saved " + std::to_string(written) + " matches -> " + matches_path_);
  else status(error, true);
}

}  // namespace dw::view
