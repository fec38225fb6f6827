// `why` asked of a session (docs/design.md §7b): the origins found in its history, the window
// they need recorded (sim/causal_history.h), and the cone over it.
#include <algorithm>
#include <set>
#include <tuple>

#include "sim/history_reader.h"
#include "sim/session.h"
#include "sim/why.h"
#include "watch/domains.h"
#include "watch/evaluator.h"
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

// The origins of several values, found in one walk back through the history: each window, four
// times longer than the one after it, re-simulated once with the cursor for all of them (the
// cursor going back where it was); false when cancelled.
bool origin_steps(Session& session, std::span<ValueAsked> values, const Control& control) {
  if (values.size() == 1) {
    const auto origin = origin_step(session, values[0].module, values[0].column, values[0].t, control);
    if (origin) values[0].origin = *origin;
    return origin.has_value();
  }
  const int64_t back = session.current();
  std::vector<size_t> pending(values.size());
  int64_t to = 0;
  for (size_t i = 0; i < values.size(); ++i) pending[i] = i, to = std::max(to, values[i].t);
  const Control step_control{.stop = control.stop};
  for (int64_t span = 16; !pending.empty(); span *= 4) {
    const int64_t from = std::max<int64_t>(0, to - span);
    const size_t n = pending.size();
    std::vector<int64_t> value;  // [(s - from) * n + k]
    std::vector<uint8_t> present;
    for (int64_t s = from; s <= to; ++s) {
      if (!session.seek(s, step_control)) {
        session.seek(back);
        return false;
      }
      const std::vector<int64_t>& now = session.state().values;
      const std::span<const uint8_t> seen = session.seen_present();
      for (size_t i : pending) {
        const ValueAsked& v = values[i];
        value.push_back(now[size_t{v.module} * session.model().variable_count() + size_t(v.column)]);
        present.push_back(seen[v.module]);
      }
    }
    std::vector<size_t> left;
    for (size_t k = 0; k < n; ++k) {
      ValueAsked& v = values[pending[k]];
      int64_t w = std::min(v.t, to);
      for (; w > from; --w) {
        const auto i = static_cast<size_t>(w - from) * n + k, before = i - n;
        if (present[i] && (!present[before] || value[i] != value[before])) break;
      }
      if (w > from || from == 0) v.origin = w;
      else left.push_back(pending[k]);
    }
    pending = std::move(left);
    to = from;
  }
  session.seek(back);
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
  if (!origin_steps(session, values, control)) return std::nullopt;
  last = 0;
  for (const ValueAsked& v : values) last = std::max(last, v.origin);
  // One step more than the cone holds: what the first event read, and its neighbours before.
  const auto history = record_window(session, window_start(values, depth), last, control);
  if (!history) return std::nullopt;
  return cone_of(*history, values, depth, narrow);
}

// The variables a match's watchpoint read of any module through its value code (aggregates'
// elements included, §7b "a match's cone"), evaluated over a window recorded around step t: each
// (module, column, step) once; nothing when cancelled.
std::optional<std::vector<ValueAsked>> value_code_reads(Session& session, const watch::Program& program, int64_t t,
                                                        std::span<const ModuleId> group, const Control& control) {
  std::vector<ValueAsked> values;
  bool expressions = false;
  for (const watch::Leaf& leaf : program.leaves) expressions |= leaf.kind == watch::LeafKind::Expression;
  if (program.aggregates.empty() || (!expressions && program.actions.empty()) ||
      group.size() < static_cast<size_t>(program.slot_count()))
    return values;
  const int64_t first = std::clamp<int64_t>(t + program.min_offset, 0, session.latest());
  const int64_t last = std::clamp<int64_t>(t + program.extent_plus, first, session.latest());
  const auto history = record_window(session, first, last, control, Recording::States);
  if (!history) return std::nullopt;
  std::vector<int> columns;
  for (const std::string& v : program.variables) columns.push_back(session.model().column(v));
  HistoryReader noter(*history, std::move(columns), session.model().universe, group, t);
  noter.note_reads = true;
  watch::EvaluatorScratch scratch(program);
  watch::Evaluator<HistoryReader> evaluator(program, noter, scratch);
  for (const watch::Leaf& leaf : program.leaves)
    if (leaf.kind == watch::LeafKind::Expression) evaluator.leaf(leaf);
  for (const watch::ActionCode& a : program.actions)
    if (a.value != watch::kNoCode) evaluator.value(a.value, 0, -1);
  std::sort(noter.read.begin(), noter.read.end());
  noter.read.erase(std::unique(noter.read.begin(), noter.read.end()), noter.read.end());
  for (const auto& [m, column, step] : noter.read) values.push_back({.module = m, .column = column, .t = step});
  return values;
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
  // What its aggregates read of their elements at the match's step.
  const auto reads = value_code_reads(session, program, t, group, control);
  if (!reads) return std::nullopt;
  std::set<std::tuple<ModuleId, int, int64_t>> asked;
  for (const ValueAsked& v : values) asked.emplace(v.module, v.column, v.t);
  for (const ValueAsked& v : *reads)
    if (asked.emplace(v.module, v.column, v.t).second) values.push_back(v);
  auto cone = cone_in_session(session, std::move(values), depth, narrow, control);
  if (cone)
    for (ConeEvent& e : cone->events) e.group = std::find(group.begin(), group.end(), e.module) != group.end();
  return cone;
}

}  // namespace dw::sim
