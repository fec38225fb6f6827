// The window's script (`dwatch view --script FILE`, docs/design.md §7a): the session's commands plus
// what only a window has — `click`, `key`, `wait`, `timeline`, `screenshot`, `screencast` (a video
// of the window: screencast.cpp), `panel`, and `press`
// and `type`, which reach a button or a text field through the platform layer as a person's mouse
// and keyboard do (a button that is hidden or cut off cannot be pressed) — and `expect-failure`,
// which lets a script go on past a command that must fail, to look at how the failure shows.
#include "app/view/debugger.h"  // first: render/gl.h before GLFW's GL header

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <imgui.h>

#include <cmath>
#include <iostream>

#include "render/annotations.h"
#include "shell/output_files.h"
#include "shell/utf8_text.h"

namespace dw::view {
namespace {

// Word i of a window command as an integer from lo to hi (`what` names it); nothing, and `error`
// says why, when it is missing or out of range.
std::optional<int64_t> word_number(const std::vector<std::string>& words, size_t i, int64_t lo, int64_t hi,
                                   const char* what, std::string& error) {
  if (i >= words.size()) {
    error = std::string(what) + " is missing";
    return std::nullopt;
  }
  char* end = nullptr;
  const long long v = std::strtoll(words[i].c_str(), &end, 10);
  if (hi < lo) {  // nothing to choose from
    error = std::string("there is no ") + what + " to choose: the list is empty";
    return std::nullopt;
  }
  if (*end || words[i].empty() || v < lo || v > hi) {
    error = std::string(what) + " must be an integer from " + std::to_string(lo) + " to " + std::to_string(hi);
    return std::nullopt;
  }
  return v;
}

}  // namespace

nlohmann::ordered_json Debugger::window_command(const std::vector<std::string>& words, std::string& error) {
  nlohmann::ordered_json answer;
  answer["cmd"] = words[0];
  settle();
  const std::string& command = words[0];
  if (command == "screenshot") screenshot_command(words, answer, error);
  else if (command == "screencast") screencast_command(words, answer, error);
  else if (command == "press" || command == "type") press_command(words, answer, error);
  else if (command == "panel") panel_command(words, answer, error);
  else input_command(words, answer, error);  // wait, key, click, timeline
  return answer;
}

// wait N | key NAME | follow M | follow off | click timeline T | timeline fit | timeline FIRST LAST |
// click match ROW | click M: what a person's keys, clicks and patience do.
void Debugger::input_command(const std::vector<std::string>& words, nlohmann::ordered_json& answer,
                             std::string& error) {
  const sim::Model& m = session_.model();
  if (words[0] == "wait") {
    const auto n = word_number(words, 1, 0, 100000, "N", error);
    if (!n) return;
    for (int64_t i = 0; i < *n; ++i) frame();
    answer["frames"] = *n;
  } else if (words[0] == "key") {
    const auto key = words.size() == 2 ? key_named(words[1]) : std::nullopt;
    if (!key) {
      error = key_usage();
      return;
    }
    press(*key);
    settle();
    frame();  // what the key shows (the help window, a fit) is drawn before the next screenshot
    answer["key"] = words[1];
    answer["current"] = readout_.at.current;
  } else if (words[0] == "follow") {
    // follow M | follow off: what T does, for any module.
    if (words.size() == 2 && words[1] == "off") {
      model_.followed.reset();
    } else {
      const auto module = word_number(words, 1, 0, int64_t(m.module_count()) - 1, "M", error);
      if (!module) return;
      model_.followed = sim::ModuleId(*module);
    }
    frame();
    answer["following"] = model_.followed ? nlohmann::ordered_json(m.universe.id(*model_.followed)) : nullptr;
    answer["camera_target"] = vec_text(model_.camera.target);
  } else if (words[0] == "click" && words.size() >= 2 && words[1] == "timeline") {
    const auto t = word_number(words, 2, 0, std::max<int64_t>(timeline_.last, 0), "T", error);
    if (!t) return;
    const float x = timeline_.x_of(*t);
    apply(model_.on_timeline_click(timeline_, x, readout_.at));
    settle();
    answer["x"] = x;
    answer["current"] = readout_.at.current;
  } else if (words[0] == "timeline") {
    // timeline fit | timeline FIRST LAST: what the wheel and a right drag do.
    if (words.size() == 2 && words[1] == "fit") {
      model_.timeline_range.fit();
    } else {
      const int64_t end = std::max({readout_.at.end - 1, readout_.at.latest, int64_t{0}});
      const auto first = word_number(words, 1, 0, end, "FIRST", error),
                 last = first ? word_number(words, 2, *first, end, "LAST", error) : std::nullopt;
      if (!last) {
        error = "timeline fit | timeline FIRST LAST: " + error;
        return;
      }
      model_.timeline_range.show(*first, *last, readout_.at);
    }
    frame();
    answer["first"] = timeline_.first;
    answer["last"] = timeline_.last;
  } else if (words[0] == "click" && words.size() >= 2 && words[1] == "match") {
    const auto row = word_number(words, 2, 0, int64_t(readout_.match_rows.size()) - 1, "ROW", error);
    if (!row) return;
    const MatchRef ref = readout_.match_rows[size_t(*row)].ref;
    std::vector<std::string> commands;
    worker_->read([&](sim::Session& s) { commands = model_.on_match_click(s, ref); });
    apply(commands);
    readout_stale_ = true;
    settle();
    frame();  // the camera centres on the group at the next frame
    answer["current"] = readout_.at.current;
    answer["selected"] = model_.selected ? nlohmann::ordered_json(m.universe.id(*model_.selected)) : nullptr;
  } else if (words[0] == "click") {
    const auto module = word_number(words, 1, 0, int64_t(m.module_count()) - 1, "M", error);
    if (!module) return;
    // Where module M shows, clicked through the same picking as the mouse.
    const glm::mat4 vp = renderer_->view_projection(camera_scene(), view_.width, view_.height);
    std::optional<glm::vec2> pixel;
    for (const render::SceneModule& s : readout_.scene.modules)
      if (s.id == sim::ModuleId(*module))
        pixel = render::project(vp, {s.pose.position[0], s.pose.position[1], s.pose.position[2]}, view_.width,
                                view_.height);
    if (!pixel) {
      error = "module " + std::to_string(*module) + " is not in the 3D view at this step";
      return;
    }
    model_.on_module_click(module_at(pixel->x, pixel->y));
    readout_stale_ = true;
    settle();
    answer["pixel"] = {pixel->x, pixel->y};
    answer["selected"] = model_.selected ? nlohmann::ordered_json(m.universe.id(*model_.selected)) : nullptr;
  }
}

// screenshot FILE: the window as it shows after the next frame, and what of the ensemble the 3D
// view shows.
void Debugger::screenshot_command(const std::vector<std::string>& words, nlohmann::ordered_json& answer,
                                  std::string& error) {
  if (words.size() != 2) {
    error = "screenshot FILE";
    return;
  }
  if (std::string clash = shell::file_clash(scenario_.inputs, {{"screenshot", words[1]}}); !clash.empty()) {
    error = clash;
    return;
  }
  window_shot_ = words[1];
  frame();
  if (!window_shot_error_.empty()) {
    error = window_shot_error_;
    return;
  }
  const render::Camera c = model_.camera.camera();
  answer["screenshot"] = words[1];
  answer["t"] = std::max<int64_t>(0, readout_.at.current);
  answer["view"] = {{"x", view_.x}, {"y", view_.y}, {"width", view_.width}, {"height", view_.height}};
  answer["camera_eye"] = vec_text(c.eye);
  answer["camera_target"] = vec_text(c.target);
  answer["color_by"] = model_.color_by;
  // What of the ensemble the 3D view shows: every module's centre inside it, and the groups'.
  std::vector<sim::ModuleId> group;
  for (const render::SceneGroup& g : readout_.scene.groups)
    group.insert(group.end(), g.modules.begin(), g.modules.end());
  answer["in_view"] = {{"modules", modules_in_view({})},
                       {"of", readout_.scene.modules.size()},
                       {"group", group.empty() ? 0 : modules_in_view(group)},
                       {"group_of", group.size()}};
}

// press NAME... | type FIELD TEXT: found where the last frame drew it, then clicked there.
void Debugger::press_command(const std::vector<std::string>& words, nlohmann::ordered_json& answer,
                             std::string& error) {
  std::string name;
  for (size_t i = 1; i < (words[0] == "type" ? std::min<size_t>(2, words.size()) : words.size()); ++i)
    name += (name.empty() ? "" : " ") + words[i];
  frame();  // the widgets as they show now
  const auto it = widgets_.find(name);
  if (it == widgets_.end()) {
    std::string shown;
    for (const auto& [n, place] : widgets_) shown += (shown.empty() ? "" : ", ") + n;
    error = "no " + std::string(words[0] == "type" ? "field" : "button") + " '" + name +
            "' is in the window now (there are: " + shown + ")";
    return;
  }
  WidgetPlace place = it->second;
  if (place.out_of_sight && !place.cut) {  // scrolled to, as a person would with the wheel
    scroll_to_ = name;
    frame();
    frame();
    place = widgets_[name];
  }
  if (place.cut || place.out_of_sight || place.disabled) {
    error = "'" + name + "' is " +
            (place.disabled ? "greyed out: a click there does nothing"
                            : "cut off or out of sight in its panel: a click there would not reach it");
    return;
  }
  if (!click_at((place.x0 + place.x1) / 2, (place.y0 + place.y1) / 2)) {
    error = "'" + name + "' lies off the screen (the window is larger than the display): the pointer cannot reach it";
    return;
  }
  if (words[0] == "type") type_text(words.size() > 2 ? words[2] : "");
  settle();
  answer[words[0] == "type" ? "field" : "button"] = name;
  if (words[0] == "type") answer["text"] = words.size() > 2 ? words[2] : "";
  answer["status"] = status_;
  answer["current"] = readout_.at.current;
}

// panel widgets | panel plots | panel timeline | panel why | panel NAME: what the window shows, as text.
void Debugger::panel_command(const std::vector<std::string>& words, nlohmann::ordered_json& answer,
                             std::string& error) {
  if (words.size() == 2 && words[1] == "widgets") {
    // Every button and field of the last frame, where it is, and whether it shows whole.
    answer["widgets"] = nlohmann::ordered_json::array();
    for (const auto& [name, place] : widgets_)
      answer["widgets"].push_back({{"name", name},
                                   {"rect", {place.x0, place.y0, place.x1, place.y1}},
                                   {"cut", place.cut},
                                   {"out_of_sight", place.out_of_sight},
                                   {"disabled", place.disabled},
                                   {"text_width", place.text_width}});
    answer["cut_labels"] = cut_labels_;
    const ImGuiViewport* vp = ImGui::GetMainViewport();
    answer["window"] = {{"width", vp->WorkSize.x}, {"height", vp->WorkSize.y}, {"too_small", panels_.too_small}};
    // Where the column's panels are (x, y, width, height): for tests that look at their folds.
    auto rect = [](const PanelRect& r) { return nlohmann::ordered_json{r.x, r.y, r.width, r.height}; };
    answer["panels"] = {{"watchpoints", rect(panels_.watchpoints)},
                        {"matches", rect(panels_.matches)},
                        {"module", rect(panels_.module)},
                        {"statistics", rect(panels_.statistics)}};
    return;
  }
  if (words.size() != 2) {
    error = kPanelUsage;
    return;
  }
  if (words[1] == "plots") {  // where the last frame drew its plots, for tests that look at them
    answer["plot_rects"] = nlohmann::ordered_json::array();
    for (const auto& r : plot_rects_) answer["plot_rects"].push_back(r);
    answer["plot_labels"] = nlohmann::ordered_json::array();
    for (const PlotLabel& l : plot_labels_) answer["plot_labels"].push_back({{"text", l.text}, {"rect", l.rect}});
    return;
  }
  if (words[1] == "timeline") {  // the steps it shows, and where
    answer["first"] = timeline_.first;
    answer["last"] = timeline_.last;
    answer["fitted"] = model_.timeline_range.fitted;
    answer["x0"] = timeline_.x0;
    answer["width"] = timeline_.width;
    answer["y0"] = timeline_y_;
    answer["height"] = timeline_height_;
    return;
  }
  if (words[1] == "pointers") {  // the pointers at the 3D view's edge, in window pixels
    answer["pointers"] = nlohmann::ordered_json::array();
    const ImVec2 scale = ImGui::GetIO().DisplayFramebufferScale;
    for (const EdgePointerMark& p : pointers_)
      answer["pointers"].push_back({{"module", p.module},
                                    {"more", p.more},
                                    {"x", view_.x / scale.x + p.at.x},
                                    {"y", view_.y / scale.y + p.at.y},
                                    {"toward", {p.toward.x, p.toward.y}}});
    return;
  }
  if (words[1] == "why") {  // the Why panel's diagram: where each dot and arrow was drawn
    for (const auto& [key, value] : why_drawn_.items()) answer[key] = value;
    return;
  }
  answer = readout_.panel(words[1], session_.model());
  if (answer.contains("error")) error = answer["error"];
}

nlohmann::ordered_json Debugger::session_command(const std::string& line, std::string& error) {
  size_t first;
  {
    std::lock_guard lock(answers_mutex_);
    first = answers_.size();
  }
  send(line);
  settle();
  std::lock_guard lock(answers_mutex_);
  if (answers_.size() <= first) return {};
  error = answers_[first].error;
  return answers_[first].json;
}

int Debugger::run_script(const watch::SourceText& script) {
  // Checked whole first, as `dwatch session` checks a script.
  struct Line {
    uint32_t number;
    std::vector<std::string> window_words;  // a window command
    std::string session_line;               // or a line of the session language
    bool expect_failure = false;            // `expect-failure COMMAND`: it must fail, and the script goes on
  };
  std::vector<Line> lines;
  std::string mistakes;
  const std::string& text = script.text();
  uint32_t number = 1;
  for (size_t begin = 0; begin < text.size(); ++number) {
    const size_t newline = text.find('\n', begin);
    const size_t stop = newline == std::string::npos ? text.size() : newline;
    std::vector<ScriptWord> words;
    for (size_t i = begin; i < stop;) {
      if (text[i] == ' ' || text[i] == '\t' || text[i] == '\r') {
        ++i;
        continue;
      }
      if (text[i] == '#') break;
      const size_t from = i;
      while (i < stop && text[i] != ' ' && text[i] != '\t' && text[i] != '\r') ++i;
      words.push_back({text.substr(from, i - from), {uint32_t(from), uint32_t(i)}});
    }
    // expect-failure COMMAND: the command as any other, after the word.
    const bool expect_failure = !words.empty() && words[0].text == "expect-failure";
    size_t command_begin = begin;
    if (expect_failure) {
      if (words.size() == 1) {
        mistakes += watch::format_diagnostics(
            script, {{{uint32_t(stop), uint32_t(stop + 1)}, "expect-failure COMMAND: the command that must fail"}});
        begin = newline == std::string::npos ? text.size() : newline + 1;
        continue;
      }
      command_begin = words[1].span.begin;
      words.erase(words.begin());
    }
    // type FIELD TEXT: TEXT is the rest of the line as written.
    if (words.size() > 3 && words[0].text == "type") {
      words[2] = {text.substr(words[2].span.begin, words.back().span.end - words[2].span.begin),
                  {words[2].span.begin, words.back().span.end}};
      words.resize(3);
    }
    if (!words.empty() && is_window_command(words[0].text)) {
      const watch::Span end{uint32_t(stop), uint32_t(stop + 1)};
      if (auto d = check_window_command(words, session_.model().module_count(), end)) {
        mistakes += watch::format_diagnostics(script, {*d});
      } else {
        std::vector<std::string> plain;
        for (const ScriptWord& w : words) plain.push_back(w.text);
        lines.push_back({number, std::move(plain), {}, expect_failure});
      }
    } else {
      auto parsed = shell_.parse(script, uint32_t(command_begin), number);
      if (auto* ds = std::get_if<std::vector<watch::Diagnostic>>(&parsed))
        mistakes += watch::format_diagnostics(script, *ds);
      else if (std::get<std::optional<shell::Command>>(parsed))
        lines.push_back({number, {}, text.substr(command_begin, stop - command_begin), expect_failure});
    }
    begin = newline == std::string::npos ? text.size() : newline + 1;
  }
  if (!mistakes.empty()) {
    std::cerr << mistakes;
    return 2;
  }
  // The pointer rests in the window's corner, over no panel, so that no tooltip covers the view.
  int width = 0, height = 0;
  glfwGetWindowSize(window_.handle(), &width, &height);
  glfwSetCursorPos(window_.handle(), width - 2, height - 2);
  settle();
  for (const Line& line : lines) {
    std::string error;
    nlohmann::ordered_json answer;
    if (!line.window_words.empty()) {
      answer = window_command(line.window_words, error);
    } else {
      answer = session_command(line.session_line, error);
    }
    if (line.expect_failure) {
      if (error.empty()) {
        std::cout.flush();
        std::cerr << script.name() << ":" << line.number
                  << ": error: expected to fail, but it went through: " << shell::answer_line(answer)
                  << " (the script stops here)\n";
        return 1;
      }
      // The failure as the window shows it (the status line), and on.
      settle();
      answer = {{"cmd", line.window_words.empty() ? line.session_line : line.window_words[0]},
                {"failed", error},
                {"status", status_}};
      error.clear();
    }
    // The screencast holds the window as the line left it: a frame, or N for `wait N`.
    const bool waits = !line.window_words.empty() && line.window_words[0] == "wait";
    if (error.empty() && !(!line.window_words.empty() && line.window_words[0] == "screencast"))
      error = film_window(waits ? answer.value("frames", int64_t{0}) : 1);
    if (!error.empty()) {
      std::cout.flush();
      std::cerr << script.name() << ":" << line.number << ": error: " << error << " (the script stops here)\n";
      return 1;
    }
    std::cout << shell::answer_line(answer) << "\n" << std::flush;
  }
  // A screencast the script did not stop ends with it.
  if (std::string error = finish_screencast(); !error.empty()) {
    std::cerr << script.name() << ": error: " << error << "\n";
    return 1;
  }
  return 0;
}

bool Debugger::click_at(float x, float y) {
  GLFWwindow* handle = window_.handle();
  glfwSetCursorPos(handle, double(x), double(y));
  // Where the pointer went: a window larger than the screen puts some of it out of reach.
  double at_x = 0, at_y = 0;
  glfwGetCursorPos(handle, &at_x, &at_y);
  if (std::abs(at_x - double(x)) > 1 || std::abs(at_y - double(y)) > 1) return false;
  ImGui_ImplGlfw_CursorEnterCallback(handle, GLFW_TRUE);
  frame();  // hovered
  ImGui_ImplGlfw_MouseButtonCallback(handle, GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, 0);
  frame();  // held
  ImGui_ImplGlfw_MouseButtonCallback(handle, GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, 0);
  frame();  // released: a button fires, a text field is active
  return true;
}

void Debugger::type_text(const std::string& text) {
  GLFWwindow* handle = window_.handle();
  auto key = [&](int k, int action, int mods) { ImGui_ImplGlfw_KeyCallback(handle, k, 0, action, mods); };
  // Ctrl+A: what the field held is replaced.
  key(GLFW_KEY_LEFT_CONTROL, GLFW_PRESS, 0);
  key(GLFW_KEY_A, GLFW_PRESS, GLFW_MOD_CONTROL);
  frame();
  key(GLFW_KEY_A, GLFW_RELEASE, GLFW_MOD_CONTROL);
  key(GLFW_KEY_LEFT_CONTROL, GLFW_RELEASE, 0);
  // The text as characters, UTF-8 decoded (the script was checked to be UTF-8).
  for (size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    const int extra = c < 0x80 ? 0 : c < 0xE0 ? 1 : c < 0xF0 ? 2 : 3;
    unsigned codepoint = extra == 0 ? c : c & (0x3Fu >> extra);
    for (int k = 1; k <= extra && i + size_t(k) < text.size(); ++k)
      codepoint = (codepoint << 6) | (static_cast<unsigned char>(text[i + size_t(k)]) & 0x3Fu);
    ImGui_ImplGlfw_CharCallback(handle, codepoint);
    i += size_t(extra) + 1;
  }
  // The field stays active (Escape would revert it): ImGui writes each edit through at once, and
  // the next click elsewhere leaves it.
  frame();
}

}  // namespace dw::view
