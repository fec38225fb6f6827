// `why` asked of a session (docs/design.md §7b): the origins found in its history, the window
// they need recorded (sim/causal_history.h), and the cone over it.
#include <algorithm>

#include "sim/session.h"
#include "sim/why.h"
#include "watch/program.h"

namespace dw::sim {
namespace {

// The origins of the values when each lies late enough in `h` for its cone (at or after
// h.first + depth + 1, or at step 0 with the window from step 0), filled in; false otherwise.
bool origins_within(const CausalHistory& h, std::vector<ValueAsked>& values, int depth) {
  for (ValueAsked& v : values) {
    const auto changed = [&](int64_t w) {
      return h.present(w, v.module) &&
             (!h.present(w - 1, v.module) || h.value(w, v.module, v.column) != h.value(w - 1, v.module, v.column));
    };
    int64_t w = v.t;
    while (w > h.first && w > 0 && !changed(w)) --w;
    if (w > 0 && w < h.first + depth + 1) return false;
    v.origin = w;
  }
  return true;
}

std::optional<Cone> cone_in_session(Session& session, std::vector<ValueAsked> values, int depth, bool narrow,
                                    const Control& control) {
  if (values.empty()) return Cone{.depth = depth, .narrow = narrow};
  // Most values changed lately: one window, twice the cone deep, often holds their origins and
  // cones, and a single pass over it answers.
  int64_t earliest = INT64_MAX, last = 0;
  for (const ValueAsked& v : values) earliest = std::min(earliest, v.t), last = std::max(last, v.t);
  int64_t first = std::max<int64_t>(0, earliest - 2 * depth - 2);
  // A keyframe at step first - 1 or later that still leaves an origin at the earliest step asked
  // its depth: the window starts just after it, so that no step before it is simulated again.
  const int64_t room = earliest - depth - 2, interval = session.keyframe_interval();
  if (room >= 0 && interval > 0 && session.keyframes() > 0) {
    const int64_t keyframe = std::min(room / interval, static_cast<int64_t>(session.keyframes()) - 1) * interval;
    if (keyframe >= first - 1) first = keyframe + 1;
  }
  {
    const auto history = record_window(session, first, last, control);
    if (!history) return std::nullopt;
    if (origins_within(*history, values, depth)) return cone_of(*history, values, depth, narrow);
  }
  last = 0;
  for (ValueAsked& v : values) {
    const auto origin = origin_step(session, v.module, v.column, v.t, control);
    if (!origin) return std::nullopt;
    v.origin = *origin;
    last = std::max(last, v.origin);
  }
  // One step more than the cone holds: what the first event read, and its neighbours before.
  const auto history = record_window(session, window_start(values, depth), last, control);
  if (!history) return std::nullopt;
  return cone_of(*history, values, depth, narrow);
}

}  // namespace

std::optional<Cone> why_value(Session& session, ModuleId m, int column, int64_t t, int depth, bool narrow,
                              const Control& control) {
  return cone_in_session(session, {ValueAsked{.module = m, .column = column, .t = t}}, depth, narrow, control);
}

std::optional<Cone> why_match(Session& session, uint32_t w, int64_t t, std::span<const ModuleId> group, int depth,
                              bool narrow, const Control& control) {
  const watch::Program& program = session.watches()[w].hosted.watchpoint.program;
  std::vector<ValueAsked> values;
  const auto read = [&](int16_t slot, int16_t variable, int16_t offset) {
    if (variable < 0 || size_t(slot) >= group.size()) return;  // id(m), or no slot's
    const int column = session.model().column(program.variables[static_cast<size_t>(variable)]);
    const int64_t at = t + offset;
    if (column < 0 || at < 0 || at > session.latest()) return;
    const ValueAsked v{.module = group[static_cast<size_t>(slot)], .column = column, .t = at};
    const bool asked = std::any_of(values.begin(), values.end(), [&](const ValueAsked& o) {
      return o.module == v.module && o.column == v.column && o.t == v.t;
    });
    if (!asked) values.push_back(v);
  };
  // The reads of its comparisons, and of its value code (expressions, actions).
  for (const watch::Leaf& leaf : program.leaves) {
    if (leaf.kind != watch::LeafKind::Compare) continue;
    read(leaf.lhs.slot, leaf.lhs.variable, leaf.lhs.offset);
    if (!leaf.rhs_is_constant) read(leaf.rhs.slot, leaf.rhs.variable, leaf.rhs.offset);
  }
  for (const std::vector<watch::ValueInstr>& code : program.codes)
    for (const watch::ValueInstr& i : code)
      if (i.op == watch::ValueOp::Term) read(i.slot, i.variable, i.offset);
  auto cone = cone_in_session(session, std::move(values), depth, narrow, control);
  if (cone)
    for (ConeEvent& e : cone->events) e.group = std::find(group.begin(), group.end(), e.module) != group.end();
  return cone;
}

}  // namespace dw::sim
