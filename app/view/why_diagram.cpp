// The Why panel's diagram read from a `why` answer (why_diagram.h), and how it is scrolled and
// zoomed.
#include "app/view/why_diagram.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace dw::view {
namespace {

using Json = nlohmann::ordered_json;

std::string words_text(const Json& words) {
  std::string text = "[";
  for (size_t i = 0; i < words.size(); ++i) text += (i ? ", " : "") + words[i].dump();
  return text + "]";
}

// Who set a value: "its program", "watchpoint w1's action", ... (docs/session.md, `why`).
std::string writer_words(const std::string& writer, const Json& event) {
  if (writer == "program") return "its program";
  if (writer == "action") return "the action of " + (event.contains("watch") ? event["watch"].dump() : "a watchpoint");
  if (writer == "intervention") return "an intervention";
  if (writer == "event") return "the scenario's [[event]]";
  return "its initial value";
}

std::string title_of(const Json& answer) {
  const Json& values = answer["values"];
  if (answer.contains("match")) {
    const Json& match = answer["match"];
    std::string slots;
    for (const auto& [name, id] : match["slots"].items()) slots += " " + name + "=" + id.dump();
    return match["watch"].get<std::string>() + " matched at step " + match["t"].dump() + " (" +
           (slots.empty() ? std::string("no module") : slots.substr(1)) + "): the cone of the " +
           std::to_string(values.size()) + " values it read";
  }
  if (values.empty()) return "why";
  const Json& v = values[0];
  const Json& origin = v["origin"];
  const std::string writer = origin["writer"].get<std::string>();
  return v["var"].get<std::string>() + " of " + v["module"].dump() + " = " + v["value"].dump() + " at step " +
         v["t"].dump() +
         (writer == "initial" ? ": its initial value, unchanged since step 0"
                              : ": set at step " + origin["step"].dump() + " by " +
                                    writer_words(writer, answer["events"][origin["event"].get<size_t>()]));
}

}  // namespace

std::optional<WhyDiagram> why_diagram(const Json& answer, const std::string& command) {
  if (!answer.is_object() || answer.value("cmd", "") != "why" || !answer.contains("events") ||
      !answer.contains("values") || !answer.contains("messages"))
    return std::nullopt;
  WhyDiagram d;
  d.command = command;
  d.title = title_of(answer);
  d.asked_at = answer.value("current", int64_t{0});
  // The columns: the group's modules in slot order, the values' modules, then the rest by id.
  std::vector<uint32_t> first_columns;
  if (answer.contains("match"))
    for (const auto& [name, id] : answer["match"]["slots"].items()) first_columns.push_back(id.get<uint32_t>());
  for (const Json& v : answer["values"]) first_columns.push_back(v["module"].get<uint32_t>());
  std::set<uint32_t> rest;
  for (const Json& e : answer["events"]) rest.insert(e["module"].get<uint32_t>());
  for (const Json& m : answer["messages"]) rest.insert({m["from"].get<uint32_t>(), m["to"].get<uint32_t>()});
  std::map<uint32_t, int> column_of;
  auto add_column = [&](uint32_t id, bool marked) {
    if (column_of.count(id)) return;
    column_of[id] = int(d.modules.size());
    d.modules.push_back(id);
    d.group_column.push_back(marked);
  };
  for (uint32_t id : first_columns) add_column(id, true);
  for (uint32_t id : rest) add_column(id, false);

  bool any = false;
  auto span = [&](int64_t t) {
    d.first = any ? std::min(d.first, t) : t;
    d.last = any ? std::max(d.last, t) : t;
    any = true;
  };
  for (const Json& v : answer["values"]) span(v["t"].get<int64_t>());
  const Json& events = answer["events"];
  // The messages by (from, to, sent, read), to tell a cause drawn as a message from one that is not.
  std::set<std::tuple<uint32_t, uint32_t, int64_t, int64_t>> sent;
  for (const Json& m : answer["messages"]) {
    WhyArrow a;
    const uint32_t from = m["from"].get<uint32_t>(), to = m["to"].get<uint32_t>();
    a.from_column = column_of[from];
    a.to_column = column_of[to];
    a.sent = m["sent"].get<int64_t>();
    a.read = m["read"].get<int64_t>();
    a.is_new = m.value("new", true);
    a.text = std::to_string(from) + " -> " + std::to_string(to) + ": sent at step " + std::to_string(a.sent) +
             ", read at step " + std::to_string(a.read) + "\nwords " + words_text(m["words"]) +
             (a.is_new ? "" : "\n(the words it sent a step before)");
    sent.insert({from, to, a.sent, a.read});
    span(a.sent);
    span(a.read);
    d.arrows.push_back(std::move(a));
  }
  for (size_t i = 0; i < events.size(); ++i) {
    const Json& e = events[i];
    WhyDot dot;
    dot.event = i;
    dot.module = e["module"].get<uint32_t>();
    dot.column = column_of[dot.module];
    dot.step = e["step"].get<int64_t>();
    dot.writer = e.value("writer", "program");
    dot.changed = !e["changed"].empty() || e.value("remove", false);
    dot.origin = e.value("origin", false);
    dot.group = e.value("group", false);
    dot.text = "module " + std::to_string(dot.module) + " at step " + std::to_string(dot.step) + ": " +
               writer_words(dot.writer, e) + (dot.origin ? " (the origin of a value asked for)" : "");
    for (const auto& [var, change] : e["changed"].items())
      dot.text += "\n  " + var + "  " + change[0].dump() + " -> " + change[1].dump();
    if (e.value("remove", false)) dot.text += "\n  removed";
    if (e["changed"].empty() && !e.value("remove", false)) dot.text += "\n  (changed no variable)";
    std::string causes;
    for (const Json& c : e["causes"]) {
      const Json& cause = events[c.get<size_t>()];
      const uint32_t m = cause["module"].get<uint32_t>();
      const int64_t s = cause["step"].get<int64_t>();
      causes += " " + std::to_string(m) + "@" + std::to_string(s);
      // A cause in another column that no message carries: a move, or a chain through events
      // the narrow cone dropped.
      if (m == dot.module || sent.count({m, dot.module, s, dot.step})) continue;
      WhyArrow link;
      link.from_column = column_of[m];
      link.to_column = dot.column;
      link.sent = s;
      link.read = dot.step;
      link.message = false;
      link.text = std::to_string(m) + "@" + std::to_string(s) + " -> " + std::to_string(dot.module) + "@" +
                  std::to_string(dot.step) + ": a cause through events the narrow cone leaves out, or a move";
      for (const Json& n : answer["neighbours"])
        if (n["module"].get<uint32_t>() == dot.module && n["step"].get<int64_t>() == dot.step && n.contains("by") &&
            n["by"].get<uint32_t>() == m)
          link.text = std::to_string(m) + "'s " + n["reason"].get<std::string>() + " changed the neighbours of " +
                      std::to_string(dot.module) + " at step " + std::to_string(dot.step);
      d.arrows.push_back(std::move(link));
    }
    if (!causes.empty()) dot.text += "\ncaused by (module@step):" + causes;
    for (const Json& n : answer["neighbours"])
      if (n["module"].get<uint32_t>() == dot.module && n["step"].get<int64_t>() == dot.step)
        dot.text += "\nneighbours +" + n["added"].dump() + " -" + n["removed"].dump() + " (" +
                    n["reason"].get<std::string>() + ")";
    span(dot.step);
    d.dots.push_back(std::move(dot));
  }
  return d;
}

void WhyView::fit(const WhyDiagram& diagram, float width, float height) {
  fitted = true;
  const float columns = float(std::max<size_t>(1, diagram.modules.size()));
  const float steps = float(diagram.last - diagram.first + 1);
  column_width = std::clamp(width / columns, kMinColumn, kMaxColumn);
  step_height = std::clamp(height / steps, kMinStep, kMaxStep);
  scroll_x = scroll_y = 0;
}

void WhyView::zoom(float factor, float y) {
  const float before = step_height;
  step_height = std::clamp(step_height * factor, 4.0f, kMaxStep * 4);
  // The step under y stays there.
  scroll_y = (scroll_y + y) * (step_height / before) - y;
  fitted = false;
}

void WhyView::pan(float dx, float dy) {
  scroll_x -= dx;
  scroll_y -= dy;
  fitted = false;
}

void WhyView::clamp(const WhyDiagram& diagram, float width, float height) {
  const float w = column_width * float(diagram.modules.size()),
              h = step_height * float(diagram.last - diagram.first + 1);
  scroll_x = std::clamp(scroll_x, 0.0f, std::max(0.0f, w - width));
  scroll_y = std::clamp(scroll_y, 0.0f, std::max(0.0f, h - height));
}

float distance_to_segment(float px, float py, float ax, float ay, float bx, float by) {
  const float dx = bx - ax, dy = by - ay, length2 = dx * dx + dy * dy;
  const float f = length2 > 0 ? std::clamp(((px - ax) * dx + (py - ay) * dy) / length2, 0.0f, 1.0f) : 0.0f;
  return std::hypot(px - (ax + f * dx), py - (ay + f * dy));
}

}  // namespace dw::view
