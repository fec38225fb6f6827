// The cone of §7b (docs/design.md) over a recorded window: a walk back from each origin along the
// causes of each event, then, for the narrow cone, the events kept and their links through the
// dropped ones. The JSON answer is at the end.
#include "sim/why.h"

#include <algorithm>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <tuple>

namespace dw::sim {
namespace {

// An event: (step, module, outside write) with -1 for the module's program.
using Key = std::tuple<int64_t, ModuleId, int>;

struct Node {
  Key key;
  int64_t bound = INT64_MAX;  // the earliest step it was walked back to
  std::set<size_t> causes;
};

ConeEvent::Writer writer_of(OutsideWrite::By by) {
  switch (by) {
    case OutsideWrite::By::Action: return ConeEvent::Writer::Action;
    case OutsideWrite::By::Intervention: return ConeEvent::Writer::Intervention;
    case OutsideWrite::By::Event: return ConeEvent::Writer::Event;
  }
  return ConeEvent::Writer::Intervention;
}

// The words module `from` sent module `to`, read at the record's step, as a sorted multiset.
std::vector<std::vector<int64_t>> sent_words(const StepRecord& rec, ModuleId from, ModuleId to) {
  std::vector<std::vector<int64_t>> words;
  for (const ReadMessage& m : rec.read_by(to))
    if (m.from == from) words.emplace_back(rec.words_of(m).begin(), rec.words_of(m).end());
  std::sort(words.begin(), words.end());
  return words;
}

class ConeWalk {
 public:
  explicit ConeWalk(const CausalHistory& history) : h_(history) {}

  size_t origin_of(const ValueAsked& v, ConeValue& answer) {
    const int64_t w = v.origin;
    answer.asked = v;
    answer.value = h_.value(w, v.module, v.column);
    Key key{w, v.module, -1};
    answer.writer = ConeEvent::Writer::Program;
    if (answer.value == h_.value_read(w, v.module, v.column) && h_.present(w - 1, v.module)) {
      const std::vector<OutsideWrite>& outside = h_.at(w).outside;
      for (size_t k = outside.size(); k-- > 0;)
        if (outside[k].module == v.module && outside[k].column == v.column && !outside[k].remove) {
          key = Key{w, v.module, static_cast<int>(k)};
          answer.writer = writer_of(outside[k].by);
          break;
        }
      if (std::get<2>(key) < 0 && w == 0) answer.writer = ConeEvent::Writer::Initial;
    }
    return visit(key, w - depth_);
  }

  void walk() {
    while (!stack_.empty()) {
      const auto [node, bound] = stack_.back();
      stack_.pop_back();
      if (nodes_[node].bound < bound) continue;  // walked further back since
      expand(node, bound);
    }
  }

  int depth_ = 3;
  std::vector<Node> nodes_;
  std::set<std::pair<int64_t, size_t>> messages_;  // (read step, index in its record)
  std::map<std::pair<int64_t, ModuleId>, NeighbourChange> neighbours_;

 private:
  // Adds the event, to be walked back to step `bound`; its index, or SIZE_MAX when it is too early.
  size_t visit(const Key& key, int64_t bound) {
    if (std::get<0>(key) < bound || std::get<0>(key) < h_.first) return SIZE_MAX;
    auto [at, added] = index_.try_emplace(key, nodes_.size());
    if (added) nodes_.push_back({key});
    Node& n = nodes_[at->second];
    if (n.bound > bound) {
      n.bound = bound;
      stack_.emplace_back(at->second, bound);
    }
    return at->second;
  }

  void cause(size_t node, size_t cause) {
    if (cause != SIZE_MAX) nodes_[node].causes.insert(cause);
  }

  void expand(size_t node, int64_t bound) {
    const auto [s, x, outside] = nodes_[node].key;
    if (outside >= 0) return;  // a root (an action's cause is its match, answered apart)
    const StepRecord& rec = h_.at(s);
    for (size_t k = 0; k < rec.outside.size(); ++k)
      if (rec.outside[k].module == x) cause(node, visit({s, x, static_cast<int>(k)}, bound));
    if (s > 0 && h_.present(s - 1, x)) cause(node, visit({s - 1, x, -1}, bound));
    const std::span<const ReadMessage> read = rec.read_by(x);
    for (size_t i = 0; i < read.size(); ++i) {
      const size_t sender = visit({read[i].sent, read[i].from, -1}, bound);
      if (sender == SIZE_MAX) continue;
      cause(node, sender);
      messages_.emplace(s, static_cast<size_t>(&read[i] - rec.read.data()));
    }
    if (h_.holds(s - 1)) neighbour_change(node, s, x, bound);
  }

  // N(x, s) against N(x, s - 1): what changed, and why.
  void neighbour_change(size_t node, int64_t s, ModuleId x, int64_t bound) {
    const auto now = h_.at(s).graph->neighbors(x), then = h_.at(s - 1).graph->neighbors(x);
    NeighbourChange change{.module = x, .step = s};
    for (ModuleId n : now)
      if (std::find(then.begin(), then.end(), n) == then.end()) change.added.push_back(n);
    for (ModuleId n : then)
      if (std::find(now.begin(), now.end(), n) == now.end()) change.removed.push_back(n);
    if (change.added.empty() && change.removed.empty()) return;
    std::vector<ModuleId> involved{x};
    involved.insert(involved.end(), change.added.begin(), change.added.end());
    involved.insert(involved.end(), change.removed.begin(), change.removed.end());
    size_t by = SIZE_MAX;
    for (ModuleId m : involved) {
      const MovingModule* moving = h_.at(s).mover(m);
      if (!moving) moving = h_.at(s - 1).mover(m);
      if (!moving) continue;
      change.reason = moving->pivot ? NeighbourChange::Reason::Pivot : NeighbourChange::Reason::Move;
      change.by = m;
      by = visit({moving->start - 1, m, -1}, bound);
      break;
    }
    if (change.reason == NeighbourChange::Reason::World) {
      const std::vector<OutsideWrite>& outside = h_.at(s).outside;
      for (size_t k = 0; k < outside.size() && by == SIZE_MAX; ++k)
        if (outside[k].remove && std::find(involved.begin(), involved.end(), outside[k].module) != involved.end()) {
          change.reason = NeighbourChange::Reason::Removal;
          change.by = outside[k].module;
          by = visit({s, outside[k].module, static_cast<int>(k)}, bound);
        }
    }
    cause(node, by);
    neighbours_[{s, x}] = std::move(change);
  }

  const CausalHistory& h_;
  std::map<Key, size_t> index_;
  std::vector<std::pair<size_t, int64_t>> stack_;
};

}  // namespace

int64_t window_start(std::span<const ValueAsked> values, int depth) {
  int64_t first = INT64_MAX;
  for (const ValueAsked& v : values) first = std::min(first, v.origin - depth - 1);
  return std::max<int64_t>(0, first);
}

namespace {

// Whether the program event (x, s) sent a message that is new.
bool sent_new(const CausalHistory& h, ModuleId x, int64_t s) {
  if (!h.holds(s + 1)) return false;
  for (ModuleId y : h.at(s).graph->neighbors(x)) {
    const auto now = sent_words(h.at(s + 1), x, y);
    if (!now.empty() && (!h.holds(s) || now != sent_words(h.at(s), x, y))) return true;
  }
  return false;
}

ConeEvent event_of(const CausalHistory& h, const Key& key) {
  const auto [s, x, outside] = key;
  ConeEvent e{.module = x, .step = s};
  if (outside >= 0) {
    const OutsideWrite& w = h.at(s).outside[static_cast<size_t>(outside)];
    e.writer = writer_of(w.by);
    e.removes = w.remove;
    e.watch = w.watch;
    e.match_t = w.match_t;
    e.match_group = w.match_group;
    if (w.column >= 0) e.changed.push_back({w.column, h.value(s - 1, x, w.column), w.value});
    return e;
  }
  for (uint32_t c = 0; c < h.variables; ++c) {
    const int64_t before = h.value_read(s, x, static_cast<int>(c)), after = h.value(s, x, static_cast<int>(c));
    if (before != after) e.changed.push_back({static_cast<int>(c), before, after});
  }
  return e;
}

}  // namespace

Cone cone_of(const CausalHistory& history, std::span<const ValueAsked> values, int depth, bool narrow) {
  Cone cone{.depth = depth, .narrow = narrow};
  ConeWalk walk(history);
  walk.depth_ = depth;
  std::vector<size_t> origins;
  for (const ValueAsked& v : values) {
    cone.values.emplace_back();
    origins.push_back(walk.origin_of(v, cone.values.back()));
  }
  walk.walk();
  const std::vector<Node>& nodes = walk.nodes_;
  // Kept: every event of the cone, or for the narrow cone the origins, the outside writes and the
  // events that changed a variable or sent a new message.
  std::vector<ConeEvent> events;
  std::vector<uint8_t> kept(nodes.size(), 1);
  for (size_t i = 0; i < nodes.size(); ++i) {
    events.push_back(event_of(history, nodes[i].key));
    const bool origin = std::find(origins.begin(), origins.end(), i) != origins.end();
    events[i].origin = origin;
    if (narrow && !origin && std::get<2>(nodes[i].key) < 0 && events[i].changed.empty())
      kept[i] = sent_new(history, std::get<1>(nodes[i].key), std::get<0>(nodes[i].key));
  }
  // Each kept event's causes: the kept events a chain of causes reaches through dropped ones.
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (!kept[i]) continue;
    std::set<size_t> seen, found;
    std::vector<size_t> todo(nodes[i].causes.begin(), nodes[i].causes.end());
    while (!todo.empty()) {
      const size_t c = todo.back();
      todo.pop_back();
      if (!seen.insert(c).second) continue;
      if (kept[c]) found.insert(c);
      else todo.insert(todo.end(), nodes[c].causes.begin(), nodes[c].causes.end());
    }
    events[i].causes.assign(found.begin(), found.end());
  }
  // In the order of their keys (step, module, writer), renumbered.
  std::vector<size_t> order, renumber(nodes.size(), SIZE_MAX);
  for (size_t i = 0; i < nodes.size(); ++i)
    if (kept[i]) order.push_back(i);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return nodes[a].key < nodes[b].key; });
  for (size_t i = 0; i < order.size(); ++i) renumber[order[i]] = i;
  for (size_t i : order) {
    ConeEvent e = std::move(events[i]);
    for (size_t& c : e.causes) c = renumber[c];
    std::sort(e.causes.begin(), e.causes.end());
    cone.events.push_back(std::move(e));
  }
  for (size_t v = 0; v < origins.size(); ++v) cone.values[v].event = renumber[origins[v]];
  std::set<Key> kept_keys;
  for (size_t i : order) kept_keys.insert(nodes[i].key);
  const auto kept_event = [&](int64_t s, ModuleId m) { return kept_keys.count(Key{s, m, -1}) > 0; };
  for (const auto& [read, index] : walk.messages_) {
    const StepRecord& rec = history.at(read);
    const ReadMessage& m = rec.read[index];
    ConeMessage message{m.from, m.to, m.sent, read, {rec.words_of(m).begin(), rec.words_of(m).end()}};
    message.is_new =
        !history.holds(m.sent) || sent_words(rec, m.from, m.to) != sent_words(history.at(m.sent), m.from, m.to);
    if (narrow && (!message.is_new || !kept_event(read, m.to) || !kept_event(m.sent, m.from))) continue;
    cone.messages.push_back(std::move(message));
  }
  for (const auto& [at, change] : walk.neighbours_)
    if (!narrow || kept_event(at.first, at.second)) cone.neighbours.push_back(change);
  return cone;
}

namespace {

const char* writer_name(ConeEvent::Writer w) {
  switch (w) {
    case ConeEvent::Writer::Program: return "program";
    case ConeEvent::Writer::Action: return "action";
    case ConeEvent::Writer::Intervention: return "intervention";
    case ConeEvent::Writer::Event: return "event";
    case ConeEvent::Writer::Initial: return "initial";
  }
  return "?";
}

const char* reason_name(NeighbourChange::Reason r) {
  switch (r) {
    case NeighbourChange::Reason::Move: return "move";
    case NeighbourChange::Reason::Pivot: return "pivot";
    case NeighbourChange::Reason::Removal: return "removal";
    case NeighbourChange::Reason::World: return "contacts";
  }
  return "?";
}

}  // namespace

std::string cone_json(const Cone& cone, const watch::Universe& universe, std::span<const std::string> watch_names) {
  using Json = nlohmann::ordered_json;
  const auto ids = [&](std::span<const ModuleId> modules) {
    Json list = Json::array();
    for (ModuleId m : modules) list.push_back(universe.id(m));
    return list;
  };
  Json j;
  Json values = Json::array();
  for (const ConeValue& v : cone.values)
    values.push_back({{"module", universe.id(v.asked.module)},
                      {"var", universe.variables[static_cast<size_t>(v.asked.column)]},
                      {"t", v.asked.t},
                      {"value", v.value},
                      {"origin", {{"step", v.asked.origin}, {"writer", writer_name(v.writer)}, {"event", v.event}}}});
  j["values"] = std::move(values);
  j["depth"] = cone.depth;
  j["narrow"] = cone.narrow;
  Json events = Json::array();
  for (const ConeEvent& e : cone.events) {
    Json event = {{"module", universe.id(e.module)}, {"step", e.step}, {"writer", writer_name(e.writer)}};
    Json changed = Json::object();
    for (const ConeEvent::Change& c : e.changed)
      changed[universe.variables[static_cast<size_t>(c.column)]] = {c.before, c.after};
    event["changed"] = std::move(changed);
    if (e.removes) event["remove"] = true;
    if (e.writer == ConeEvent::Writer::Action) {
      event["watch"] = e.watch < watch_names.size() ? Json(watch_names[e.watch]) : Json(nullptr);
      event["match"] = e.match_t < 0 ? Json(nullptr) : Json{{"t", e.match_t}, {"group", ids(e.match_group)}};
    }
    event["causes"] = e.causes;
    if (e.origin) event["origin"] = true;
    if (e.group) event["group"] = true;
    events.push_back(std::move(event));
  }
  j["events"] = std::move(events);
  Json messages = Json::array();
  for (const ConeMessage& m : cone.messages) {
    Json message = {{"from", universe.id(m.from)},
                    {"to", universe.id(m.to)},
                    {"sent", m.sent},
                    {"read", m.read},
                    {"words", m.words}};
    if (!cone.narrow) message["new"] = m.is_new;
    messages.push_back(std::move(message));
  }
  j["messages"] = std::move(messages);
  Json neighbours = Json::array();
  for (const NeighbourChange& n : cone.neighbours) {
    Json change = {{"module", universe.id(n.module)},
                   {"step", n.step},
                   {"added", ids(n.added)},
                   {"removed", ids(n.removed)},
                   {"reason", reason_name(n.reason)}};
    if (n.reason != NeighbourChange::Reason::World) change["by"] = universe.id(n.by);
    neighbours.push_back(std::move(change));
  }
  j["neighbours"] = std::move(neighbours);
  return j.dump();
}

}  // namespace dw::sim
