#include "app/view/view_model.h"

#include "shell/command.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iterator>
#include <numeric>

namespace dw::view {

OrbitCamera OrbitCamera::looking(const render::Camera& camera) {
  OrbitCamera o;
  o.target = camera.target;
  const glm::vec3 back = camera.eye - camera.target;
  o.distance = std::max(1e-3f, glm::length(back));
  o.pitch = std::asin(std::clamp(back.z / o.distance, -1.0f, 1.0f));
  o.yaw = std::atan2(back.y, back.x);
  return o;
}

glm::vec3 OrbitCamera::eye() const {
  const glm::vec3 back(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch));
  return target + back * distance;
}

render::Camera OrbitCamera::camera() const {
  render::Camera c;
  c.eye = eye();
  c.target = target;
  return c;
}

void OrbitCamera::orbit(float dx, float dy) {
  constexpr float kRadiansPerPixel = 0.01f;
  constexpr float kMaxPitch = glm::radians(89.0f);
  yaw -= dx * kRadiansPerPixel;
  pitch = std::clamp(pitch + dy * kRadiansPerPixel, -kMaxPitch, kMaxPitch);
}

void OrbitCamera::pan(float dx, float dy, int view_height) {
  const render::Camera c = camera();
  const glm::vec3 forward = glm::normalize(c.target - c.eye);
  const glm::vec3 right = glm::normalize(glm::cross(forward, c.up));
  const glm::vec3 up = glm::cross(right, forward);
  const float per_pixel = 2 * distance * std::tan(c.fov_y * 0.5f) / float(std::max(1, view_height));
  target += (-dx * right + dy * up) * per_pixel;
}

void OrbitCamera::zoom(float notches) { distance = std::clamp(distance * std::pow(0.9f, notches), 0.5f, 1e5f); }

int64_t Timeline::step_at(float x) const {
  if (last <= first) return first;
  const double f = (double(x) - x0) / std::max(1e-6f, width);
  const int64_t t = first + int64_t(std::floor(f * double(last - first + 1)));
  return std::clamp(t, first, last);
}

float Timeline::x_of(int64_t t) const {
  const double steps = double(std::max<int64_t>(1, last - first + 1));
  return x0 + float((double(t - first) + 0.5) / steps * width);
}

namespace {
// The last step the timeline can show: the scenario's end, or the latest when simulated past it.
int64_t timeline_end(const Position& at) { return std::max({at.end - 1, at.latest, int64_t{0}}); }
}  // namespace

std::pair<int64_t, int64_t> TimelineRange::shown(const Position& at) const {
  const int64_t end = timeline_end(at);
  if (!fitted) return {first, std::min(last, end)};
  const int64_t latest = std::max<int64_t>(at.latest, 0);
  return {0, std::min(end, latest + std::max(kMinSpan, latest / 8))};
}

void TimelineRange::show(int64_t from, int64_t to, const Position& at) {
  const int64_t end = timeline_end(at);
  int64_t span = std::clamp(to - from, std::min(kMinSpan, end), end);
  from = std::clamp(from, int64_t{0}, end - span);
  first = from;
  last = from + span;
  fitted = false;
}

void TimelineRange::zoom(double factor, int64_t about, const Position& at) {
  const auto [from, to] = shown(at);
  const double span = double(to - from), share = span > 0 ? double(about - from) / span : 0.5;
  const auto next = int64_t(std::llround(span * factor));
  const int64_t begin = about - int64_t(std::llround(share * double(next)));
  show(begin, begin + next, at);
}

void TimelineRange::pan(int64_t steps, const Position& at) {
  const auto [from, to] = shown(at);
  show(from + steps, to + steps, at);
}

PanelLayout panel_layout(float x, float y, float width, float height, int lanes, bool why, bool tall_tabs) {
  PanelLayout l;
  l.too_small = width < PanelLayout::kMinWidth || height < PanelLayout::kMinHeight;
  // The column: wide enough for the editor's choices and the matches' slots on one line.
  const float column = std::clamp(width * 0.33f, 400.0f, 560.0f), left = std::max(0.0f, width - column);
  // Under a narrow view the transport's buttons wrap onto more rows: the bar grows so that the
  // timeline still shows whole.
  // A lane is 14 pixels; at most 8 are given room (more scroll).
  const float transport = (left >= 1000 ? 178 : 225) + 14.0f * float(std::clamp(lanes, 2, 8));
  l.view = {x, y, left, std::max(0.0f, height - transport)};
  l.transport = {x, y + l.view.height, left, height - l.view.height};
  if (why) {  // the space-time diagram takes the view's right part, the ensemble keeps the rest
    const float diagram = std::clamp(left * 0.42f, 360.0f, 600.0f);
    l.why = {x + left - diagram, y, diagram, l.view.height};
    l.view.width = std::max(0.0f, left - diagram);
  }
  // Watchpoints and the editor, Matches, Module, Statistics, top to bottom.
  // The Module panel has room for its interventions, variables and plot unscrolled at 1000 pixels;
  // in a low window the matches keep room for a few rows, and the statistics give it up.
  const float tall[] = {0.31f, 0.22f, 0.31f, 0.16f}, low[] = {0.30f, 0.28f, 0.27f, 0.15f};
  // The group, marks and diff tabs list rows: the matches give them room (the Module panel keeps
  // its plot whole: at 0.28 it was squeezed to 40 pixels, its steps cut, with rows to spare here).
  const float tabs[] = {0.26f, 0.15f, 0.31f, 0.28f};
  const float* shares = tall_tabs ? tabs : height >= 800 ? tall : low;
  PanelRect* column_panels[] = {&l.watchpoints, &l.matches, &l.module, &l.statistics};
  float top = y;
  for (size_t i = 0; i < std::size(column_panels); ++i) {
    const float h = i + 1 == std::size(column_panels) ? y + height - top : std::round(height * shares[i]);
    *column_panels[i] = {x + left, top, width - left, h};
    top += h;
  }
  return l;
}

std::vector<uint32_t> lane_density(std::span<const int64_t> steps, const Timeline& timeline, int columns) {
  std::vector<uint32_t> counts(size_t(std::max(0, columns)), 0);
  if (columns <= 0) return counts;
  // The column a step falls in grows with the step: each column's first match is a binary search
  // away, so a lane costs columns x log(matches), however many matches there are.
  auto column = [&](int64_t t) {
    return std::clamp(int((timeline.x_of(t) - timeline.x0) / timeline.width * float(columns)), 0, columns - 1);
  };
  auto first = std::lower_bound(steps.begin(), steps.end(), timeline.first);
  const auto end = std::upper_bound(first, steps.end(), timeline.last);
  for (int c = 0; c < columns && first != end; ++c) {
    const auto next = std::partition_point(first, end, [&](int64_t t) { return column(t) <= c; });
    counts[size_t(c)] = uint32_t(next - first);
    first = next;
  }
  return counts;
}

std::optional<int64_t> next_match(std::span<const int64_t> steps, int64_t t) {
  auto it = std::upper_bound(steps.begin(), steps.end(), t);
  if (it == steps.end()) return std::nullopt;
  return *it;
}

std::optional<int64_t> previous_match(std::span<const int64_t> steps, int64_t t) {
  auto it = std::lower_bound(steps.begin(), steps.end(), t);
  if (it == steps.begin()) return std::nullopt;
  return *std::prev(it);
}

MatchRows filter_matches(const sim::Session& session, const MatchFilter& filter, size_t limit) {
  MatchRows result;
  std::vector<MatchRef> all, one, merged;
  auto step_of = [&](const MatchRef& r) { return session.matches(r.watch).t[r.index]; };
  for (uint32_t w = 0; w < session.watches().size(); ++w) {
    if (filter.watch >= 0 && uint32_t(filter.watch) != w) continue;
    const sim::MatchList& list = session.matches(w);
    const size_t k = size_t(session.watches()[w].hosted.watchpoint.program.slot_count());
    one.clear();
    for (size_t i = 0; i < list.size(); ++i) {
      if (filter.module) {
        auto first = list.slots.begin() + std::ptrdiff_t(i * k);
        if (std::find(first, first + std::ptrdiff_t(k), *filter.module) == first + std::ptrdiff_t(k)) continue;
      }
      one.push_back({w, i});
    }
    // Each list is in step order already: merging them (stably, earlier watchpoints first) gives
    // the default order in linear time, which matters while the window plays.
    merged.clear();
    std::merge(all.begin(), all.end(), one.begin(), one.end(), std::back_inserter(merged),
               [&](const MatchRef& a, const MatchRef& b) { return step_of(a) < step_of(b); });
    std::swap(all, merged);
  }
  // Ties keep the session's order (by step, then slot ids), so the table never shuffles.
  auto key = [&](const MatchRef& r) -> std::pair<int64_t, int64_t> {
    const sim::MatchList& list = session.matches(r.watch);
    switch (filter.order) {
      case MatchFilter::Order::Step: return {list.t[r.index], 0};
      case MatchFilter::Order::Watch: return {r.watch, list.t[r.index]};
      case MatchFilter::Order::Detected: return {list.detected[r.index], list.t[r.index]};
    }
    return {0, 0};
  };
  if (filter.order != MatchFilter::Order::Step || filter.descending)
    std::stable_sort(all.begin(), all.end(), [&](const MatchRef& a, const MatchRef& b) {
      return filter.descending ? key(b) < key(a) : key(a) < key(b);
    });
  result.total = all.size();
  if (all.size() > limit) all.resize(limit);
  result.rows = std::move(all);
  return result;
}

namespace {

struct KeyEntry {
  Key key;
  std::string_view name;
};
constexpr KeyEntry kKeys[] = {
    {Key::Space, "space"}, {Key::Right, "right"}, {Key::Left, "left"}, {Key::N, "n"},
    {Key::P, "p"},         {Key::F, "f"},         {Key::Z, "z"},       {Key::Y, "y"},
    {Key::T, "t"},         {Key::I, "i"},         {Key::C, "c"},       {Key::Home, "home"},
    {Key::End, "end"},     {Key::F1, "f1"},       {Key::F12, "f12"},   {Key::Escape, "escape"},
};

}  // namespace

// In any case: the README writes F1, a script may write f1.
std::string key_usage() {
  std::string names;
  for (const KeyEntry& e : kKeys) names += (names.empty() ? "" : ", ") + std::string(e.name);
  return "key NAME: one of " + names;
}

std::optional<Key> key_named(std::string_view name) {
  for (const KeyEntry& e : kKeys)
    if (std::equal(e.name.begin(), e.name.end(), name.begin(), name.end(),
                   [](char a, char b) { return a == std::tolower(static_cast<unsigned char>(b)); }))
      return e.key;
  return std::nullopt;
}

bool is_window_command(std::string_view word) {
  return word == "click" || word == "key" || word == "wait" || word == "screenshot" || word == "screencast" ||
         word == "panel" || word == "timeline" || word == "press" || word == "type" || word == "follow";
}

std::optional<watch::Diagnostic> check_window_command(std::span<const ScriptWord> words, uint32_t module_count,
                                                      watch::Span end_of_line) {
  auto at = [&](size_t i) { return i < words.size() ? words[i].span : end_of_line; };
  auto mistake = [&](size_t i, std::string message) { return watch::Diagnostic{at(i), std::move(message)}; };
  // As the session's commands: a file or name goes into JSON answers and to the file system.
  for (size_t i = 0; i < words.size(); ++i)
    if (watch::first_non_utf8(words[i].text))
      return mistake(i, "a byte that is not UTF-8 text: names and files are read as UTF-8");
  auto integer = [&](size_t i, int64_t lo, int64_t hi, const char* what) -> std::optional<watch::Diagnostic> {
    if (i >= words.size()) return mistake(i, std::string(what) + " is missing");
    const std::string& w = words[i].text;
    char* end = nullptr;
    const long long v = std::strtoll(w.c_str(), &end, 10);
    if (w.empty() || *end || v < lo || v > hi)
      return mistake(
          i, std::string(what) + " must be an integer from " + std::to_string(lo) + " to " + std::to_string(hi));
    return std::nullopt;
  };
  const std::string& name = words[0].text;
  size_t want = 2;
  std::optional<watch::Diagnostic> d;
  if (name == "click") {
    if (words.size() > 1 && (words[1].text == "match" || words[1].text == "timeline")) {
      want = 3;
      d = integer(2, 0, int64_t{1} << 40, words[1].text == "match" ? "ROW" : "T");
    } else {
      d = integer(1, 0, int64_t{module_count} - 1, "M");
    }
  } else if (name == "key") {
    if (words.size() < 2 || !key_named(words[1].text)) d = mistake(1, key_usage());
  } else if (name == "wait") {
    d = integer(1, 0, 100'000, "N");
  } else if (name == "follow") {
    if (words.size() < 2 || words[1].text != "off") d = integer(1, 0, int64_t{module_count} - 1, "M (or off)");
  } else if (name == "screenshot") {
    if (words.size() < 2) d = mistake(1, "screenshot FILE: the PNG to write");
  } else if (name == "screencast") {
    if (words.size() < 2)
      d = mistake(1, "screencast FILE | screencast stop: the video of the window (.mp4, .webm), or its end");
  } else if (name == "panel") {
    static const char* kPanels[] = {"position", "matches",  "watchpoints", "inspector", "group",
                                    "plots",    "timeline", "widgets",     "pointers",  "why"};
    if (words.size() < 2 || std::find(std::begin(kPanels), std::end(kPanels), words[1].text) == std::end(kPanels))
      d = mistake(1, kPanelUsage);
  } else if (name == "press") {
    want = words.size();  // the button's label: the rest of the line
    if (words.size() < 2) d = mistake(1, "press BUTTON: the label of the button to press");
  } else if (name == "type") {
    want = std::max<size_t>(3, words.size());  // the text: the rest of the line
    if (words.size() < 2) d = mistake(1, "type FIELD TEXT: the field to type into, and the text");
  } else if (name == "timeline") {
    if (words.size() == 2 && words[1].text == "fit") {
    } else if (words.size() < 2 || words[1].text == "fit") {
      d = mistake(1, "timeline fit | timeline FIRST LAST: the steps the timeline shows");
    } else {
      want = 3;
      d = integer(1, 0, int64_t{1} << 40, "FIRST");
      if (!d) d = integer(2, 0, int64_t{1} << 40, "LAST");
    }
  }
  if (!d && words.size() > want)
    d = mistake(want, "'" + name + "' takes " + std::to_string(want - 1) + " more word" + (want == 2 ? "" : "s"));
  return d;
}

const std::vector<KeyHelp>& key_help() {
  static const std::vector<KeyHelp> help = {
      {"Space", "play / pause"},
      {"Right", "one step forward"},
      {"Left", "one step back (a seek: nothing is lost)"},
      {"Home / End", "step 0 / the latest step"},
      {"N / P", "next / previous match of the chosen watchpoint"},
      {"F", "fit the ensemble into the view"},
      {"Z", "zoom onto the selection (and its group)"},
      {"T", "the camera follows the selected module (again: it stays)"},
      {"I", "isolate: only the groups and the selection (again: everything)"},
      {"C", "contacts: the physics' contact points, and their normals as long as their impulse (again: off)"},
      {"Y", "why: the causal history of the selected module's last changed variable"},
      {"F12", "screenshot of the 3D view (PNG, as dwatch render draws it)"},
      {"F1", "this help"},
      {"Escape", "cancel the work in progress; close the help"},
      {"Left drag", "orbit"},
      {"Right or middle drag", "pan"},
      {"Wheel", "zoom (over the timeline: zoom its steps; right drag there: pan them)"},
      {"Click", "select a module (click empty space to clear)"},
  };
  return help;
}

std::string answer_words(const nlohmann::ordered_json& a) {
  const std::string cmd = a.value("cmd", "");
  const std::string verb = cmd.substr(0, cmd.find(' '));
  auto number = [&](const char* key) { return std::to_string(a.value(key, int64_t{0})); };
  // A run stopped by a pause, or by the match it was asked to run to.
  for (const char* key : {"paused", "matched"}) {
    if (!a.contains(key) || !a[key].is_object()) continue;
    const auto& p = a[key];
    std::string group;
    if (p.contains("group"))
      for (const auto& [slot, module] : p["group"].items())
        group += (group.empty() ? "" : " ") + slot + "=" + module.dump();
    std::string words = std::string(key == std::string_view("paused") ? "paused" : "stopped") + " at step " +
                        std::to_string(p.value("t", int64_t{0})) + " on " +
                        (key == std::string_view("paused") ? "" : "a match of ") + p.value("watch", "") + ": " + group;
    if (p.value("detected", int64_t{0}) != p.value("t", int64_t{0}))
      words += " (found at step " + std::to_string(p.value("detected", int64_t{0})) + ")";
    if (const int64_t n = p.value("matches", int64_t{1}); n > 1)
      words += ", " + std::to_string(n) + " matches at that step";
    return words;
  }
  std::string words;
  if (verb == "action") {
    const auto does = [](const std::string& action, bool before) -> std::string {
      if (action == "pause") return before ? "paused on them" : "pauses on";
      if (action == "log") return before ? "logged them" : "logs";
      return before ? "counted them" : "counts";
    };
    words = a.value("watch", "") + " " + does(a.value("action", ""), false) + " its matches from now on (it " +
            does(a.value("was", ""), true) + " before)";
  } else if (a.contains("watch") && a.contains("index"))
    words = "watchpoint " + a.value("watch", "") + " (" + a.value("algorithm", "") + ", " + a.value("action", "") +
            "): " + number("matches") + " matches so far";
  else if (a.contains("save"))
    words = "saved the session as " + a.value("save", "") + " (" +
            counted(a.value("watches", int64_t{0}), "watchpoint") + ", " +
            counted(a.value("interventions", int64_t{0}), "intervention") + ")";
  else if (a.contains("record"))
    words = "recorded steps 0 to " + std::to_string(a.value("steps", int64_t{0}) - 1) + " to " + a.value("record", "");
  else if (a.contains("render")) words = "drew step " + number("t") + " to " + a.value("render", "");
  else if (a.contains("intervention"))
    words = "intervention at step " + std::to_string(a["intervention"].value("at", int64_t{0})) +
            (a.value("dropped_steps", int64_t{0}) > 0 ? ", " + number("dropped_steps") + " later steps dropped" : "");
  else if (a.contains("reloaded")) words = "scripts reloaded";
  else if (verb == "diff")
    words = number("count") + " modules differ between steps " + number("a") + " and " + number("b");
  else if (a.contains("marks")) words = counted(int64_t(a["marks"].size()), "bookmark");
  else if (a.contains("found"))  // find: where it went, or how far it looked in vain
    words = a["found"].is_null() ? "found none: searched to step " + number("searched_to") + ", the cursor stays"
                                 : "found at step " + number("found");
  else words = verb.empty() ? "done" : verb + ": done";
  if (a.contains("current"))
    words += (words.empty() ? "" : "; ") + std::string("at ") +
             position_words(a.value("current", int64_t{0}), a.value("latest", int64_t{0}));
  if (a.value("cancelled", false)) words += " (cancelled)";
  if (a.contains("warning")) words += "; but " + a.value("warning", "");
  return words;
}

std::string position_words(int64_t current, int64_t latest) {
  return "step " + std::to_string(current) + " (0 to " + std::to_string(latest) + " simulated)";
}

std::string counted(int64_t n, const std::string& one) { return std::to_string(n) + " " + one + (n == 1 ? "" : "s"); }

namespace command {
std::string step(int64_t n) { return "step " + std::to_string(n); }
std::string run() { return "run"; }
std::string continue_run() { return "continue"; }
std::string run_to_match(std::string_view watch) { return "run --to-match " + std::string(watch); }
std::string action(std::string_view watch, sim::MatchAction action) {
  return "action " + std::string(watch) + " " + std::string(sim::action_name(action));
}
std::string reload() { return "reload"; }
std::string run_to(int64_t t) { return "run " + std::to_string(t); }
std::string seek(int64_t t) { return "seek " + std::to_string(t); }
std::string set(sim::ModuleId m, std::string_view variable, int64_t value) {
  return "set " + std::to_string(m) + " " + std::string(variable) + " " + std::to_string(value);
}
std::string remove(sim::ModuleId m) { return "remove " + std::to_string(m); }
std::string push(sim::ModuleId m, glm::vec3 impulse) {
  auto number = [](float f) {
    std::string s = std::to_string(f);
    s.erase(s.find_last_not_of('0') + 1);
    if (s.back() == '.') s.pop_back();
    return s;
  };
  return "push " + std::to_string(m) + " " + number(impulse.x) + " " + number(impulse.y) + " " + number(impulse.z);
}
std::string watch(std::string_view name, std::string_view options, std::string_view text) {
  // One command a line: the watchpoint's own line breaks become spaces (the language ignores them).
  std::string flat(text);
  std::replace(flat.begin(), flat.end(), '\n', ' ');
  std::replace(flat.begin(), flat.end(), '\r', ' ');
  return "watch " + std::string(name) + " " + (options.empty() ? "" : std::string(options) + " ") + flat;
}
std::string unwatch(std::string_view name) { return "unwatch " + std::string(name); }
std::string save(const std::string& file, bool overwrite) {
  return "save " + shell::command_word(file) + (overwrite ? " overwrite" : "");
}
std::string record(const std::string& file) { return "record " + shell::command_word(file); }
std::string find_change(sim::ModuleId m, std::string_view variable, bool back) {
  return std::string("find ") + (back ? "prev " : "next ") + std::to_string(m) + " " + std::string(variable);
}
std::string find_holding(std::span<const sim::ModuleId> group, std::span<const std::string> slots,
                         std::string_view expression, bool back) {
  std::string line = std::string("find ") + (back ? "prev" : "next");
  for (sim::ModuleId m : group) line += " " + std::to_string(m);
  line += " when modules(";
  for (size_t i = 0; i < slots.size(); ++i) line += (i ? " " : "") + slots[i];
  return line + "); " + std::string(expression);
}
std::string mark(int64_t t, std::string_view note) {
  // One line: the note is the rest of it, before any '#' (a comment), so those are left out.
  std::string line = "mark " + std::to_string(t);
  std::string kept;
  for (char c : note)
    if (c != '\n' && c != '\r' && c != '#') kept += c;
  return kept.empty() ? line : line + " " + kept;
}
std::string unmark(int64_t t) { return "unmark " + std::to_string(t); }
std::string diff(int64_t a, int64_t b) { return "diff " + std::to_string(a) + " " + std::to_string(b); }
}  // namespace command

std::vector<std::string> ViewModel::on_key(Key key, const Position& at, std::span<const int64_t> chosen_steps,
                                           std::string_view chosen_watch) {
  switch (key) {
    case Key::Space: playing = !playing; return {};
    case Key::Right: playing = false; return {command::step(1)};
    case Key::Left:
      playing = false;
      if (at.current <= 0) return {};
      return {command::seek(at.current - 1)};
    case Key::Home: playing = false; return {command::seek(0)};
    case Key::End: playing = false; return {command::seek(at.latest)};
    case Key::N:
    case Key::P: {
      playing = false;
      const auto t = key == Key::N ? next_match(chosen_steps, at.current) : previous_match(chosen_steps, at.current);
      if (!t && key == Key::N && !chosen_watch.empty()) return {command::run_to_match(chosen_watch)};
      if (!t) return {};
      // A match ahead of the latest step cannot be known yet; one behind is a seek.
      return {*t <= at.latest ? command::seek(*t) : command::run_to(*t)};
    }
    case Key::F: camera_placed = false, followed.reset(); return {};
    case Key::Z: focus_selection = selected.has_value(); return {};
    case Key::T:  // follow the selection, or stop following
      followed = followed || !selected ? std::nullopt : selected;
      return {};
    case Key::I: isolate = !isolate; return {};
    case Key::C: contacts = !contacts; return {};
    case Key::Y: return {};  // the window asks `why` (it knows the module's history)
    case Key::F1: show_help = !show_help; return {};
    case Key::F12: screenshot_requested = true; return {};
    case Key::Escape: show_help = false; return {};
  }
  return {};
}

std::vector<std::string> ViewModel::on_timeline_click(const Timeline& timeline, float x, const Position& at) {
  playing = false;
  const int64_t t = timeline.step_at(x);
  if (t == at.current) return {};
  // Past the latest step the session must run there (stopping at a pause on the way).
  if (t > at.latest) return {command::run_to(t)};
  return {command::seek(t)};
}

std::vector<std::string> ViewModel::on_match_click(const sim::Session& session, MatchRef match) {
  playing = false;
  selected_match = match;
  const sim::MatchList& list = session.matches(match.watch);
  const size_t k = size_t(session.watches()[match.watch].hosted.watchpoint.program.slot_count());
  if (k > 0) {  // a zero-slot match (docs/design.md §4c) has no module to select
    selected = list.slots[match.index * k];
    reveal_group = true;
  }
  return {command::seek(list.t[match.index])};
}

void ViewModel::on_module_click(std::optional<sim::ModuleId> module) {
  selected = module;
  if (!module) selected_match.reset();
}

int64_t ViewModel::steps_due(double seconds) const {
  if (speed <= 0) return 1;  // as fast as possible: one step a request, requests back to back
  return int64_t(std::floor(seconds * speed));
}

}  // namespace dw::view
