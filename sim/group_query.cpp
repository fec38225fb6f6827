// Searching the history for a change or a condition (sim/group_query.h): windows growing away from
// the current step, each re-simulated once from the keyframes, so that a near answer is quick and
// a far one costs about one pass over the history.
#include "sim/group_query.h"

#include <algorithm>

#include "sim/causal_history.h"
#include "sim/history_reader.h"
#include "sim/session.h"
#include "sim/unknown_variables.h"
#include "watch/evaluator.h"

namespace dw::sim {
namespace {

constexpr int64_t kFirstWindow = 16;  // steps; each next window is four times longer
// Values a recorded window may hold (8 bytes each): a long search over a large ensemble records
// its steps a part at a time.
constexpr size_t kWindowValues = size_t{16} << 20;

// Calls look(lo, hi) on windows of steps growing away from the current step, nearest first,
// until it finds (returns a step), is cancelled (nullopt from look) or the history ends.
template <class Look>
Found search(const Session& session, SearchDirection direction, Look&& look) {
  const int64_t t = session.current(), latest = session.latest();
  for (int64_t span = kFirstWindow, near = direction == SearchDirection::Back ? t - 1 : t + 1;; span *= 4) {
    int64_t lo = near, hi = near;
    if (direction == SearchDirection::Back) {
      if (near < 0) return {};
      lo = std::max<int64_t>(0, near - span + 1);
      near = lo - 1;
    } else {
      if (near > latest) return {};
      hi = std::min(latest, near + span - 1);
      near = hi + 1;
    }
    const std::optional<std::optional<int64_t>> found = look(lo, hi);
    if (!found) return {.cancelled = true};
    if (*found) return {.step = *found};
  }
}

// The step of [lo, hi] nearest the current one at which `at(s)` is true.
template <class At>
std::optional<int64_t> nearest(SearchDirection direction, int64_t lo, int64_t hi, At&& at) {
  if (direction == SearchDirection::Back) {
    for (int64_t s = hi; s >= lo; --s)
      if (at(s)) return s;
  } else {
    for (int64_t s = lo; s <= hi; ++s)
      if (at(s)) return s;
  }
  return std::nullopt;
}

}  // namespace

Found find_change(Session& session, ModuleId m, int column, SearchDirection direction, const Control& control) {
  if (!session.has_history()) return {};  // nothing to re-simulate: no step is known but the latest
  return search(session, direction, [&](int64_t lo, int64_t hi) -> std::optional<std::optional<int64_t>> {
    // From the step before the window, which a change at its first step is against.
    const int64_t from = std::max<int64_t>(0, lo - 1);
    std::vector<uint8_t> present;
    const auto values = session.series(m, column, from, hi, control, &present);
    if (!values) return std::nullopt;
    return nearest(direction, lo, hi, [&](int64_t s) {
      const auto i = static_cast<size_t>(s - from);
      if (!present[i]) return false;
      return s == 0 || !present[i - 1] || (*values)[i] != (*values)[i - 1];
    });
  });
}

std::string why_undecidable(const watch::Program& program, size_t group_size) {
  const auto counted = [](size_t n, const char* one) { return std::to_string(n) + " " + one + (n == 1 ? "" : "s"); };
  if (program.slot_count() != static_cast<int>(group_size))
    return "the condition has " + counted(size_t(program.slot_count()), "slot") + " and the group " +
           counted(group_size, "module") + ": one module a slot, in order";
  if (program.kept_columns > 0)
    return "windows kept by each module (since, times[k], once[k] over one slot) are worked out over the run "
           "and not kept in the history: compile the condition with its windows written out";
  return {};
}

std::variant<watch::Watchpoint, std::string> condition_on_slots(const Model& model,
                                                                std::span<const std::string> slot_names,
                                                                std::string_view expression) {
  std::string text = "modules(";
  for (size_t i = 0; i < slot_names.size(); ++i) text += (i ? " " : "") + slot_names[i];
  text += "); ";
  const size_t prefix = text.size();
  text += expression;
  auto compiled = watch::compile_watchpoint("pin", watch::SourceText("<pin>", text), watch::WindowKeeping::WrittenOut);
  std::vector<watch::Diagnostic> mistakes;
  if (auto* error = std::get_if<watch::CompileError>(&compiled)) mistakes = std::move(error->diagnostics);
  else mistakes = unknown_variable_mistakes(model, std::get<watch::Watchpoint>(compiled));
  if (!mistakes.empty()) {
    const watch::Diagnostic& d = mistakes.front();
    const size_t column = d.span.begin >= prefix ? d.span.begin - prefix + 1 : 1;
    return "column " + std::to_string(column) + ": " + d.message;
  }
  return std::get<watch::Watchpoint>(std::move(compiled));
}

std::optional<std::vector<watch::Truth>> truth_over(Session& session, const watch::Program& program,
                                                    std::span<const ModuleId> group, int64_t from, int64_t to,
                                                    const Control& control) {
  const Model& model = session.model();
  std::vector<int> columns;
  for (const std::string& v : program.variables) columns.push_back(model.column(v));
  const size_t per_step = std::max<size_t>(1, size_t{model.module_count()} * model.variable_count());
  const auto part = static_cast<int64_t>(std::max<size_t>(1, kWindowValues / per_step));
  watch::EvaluatorScratch scratch(program);
  std::vector<watch::Truth> leaves(program.leaves.size()), stack(static_cast<size_t>(program.max_stack));
  std::vector<watch::Truth> truths;
  for (int64_t lo = from; lo <= to; lo += part) {
    const int64_t hi = std::min(to, lo + part - 1);
    const int64_t first = std::clamp<int64_t>(lo + program.min_offset, 0, session.latest());
    const int64_t last = std::clamp<int64_t>(hi + program.extent_plus, first, session.latest());
    const auto history = record_window(session, first, last, control, Recording::States);
    if (!history) return std::nullopt;
    HistoryReader reader(*history, columns, model.universe, group, lo);
    watch::Evaluator<HistoryReader> evaluator(program, reader, scratch);
    for (int64_t t = lo; t <= hi; ++t) {
      reader.at(t);
      for (size_t i = 0; i < program.leaves.size(); ++i) {
        const watch::Leaf& l = program.leaves[i];
        switch (l.kind) {
          case watch::LeafKind::Compare: {
            const watch::Value a = reader.value(group[size_t(l.lhs.slot)], l.lhs.variable, t + l.lhs.offset);
            const watch::Value b = l.rhs_is_constant
                                       ? watch::known_value(l.constant)
                                       : reader.value(group[size_t(l.rhs.slot)], l.rhs.variable, t + l.rhs.offset);
            leaves[i] = watch::compare_values(l.op, a, b);
            break;
          }
          case watch::LeafKind::Neighbor:
            leaves[i] = reader.adjacent(group[size_t(l.x)], t + l.offset, group[size_t(l.y)]);
            break;
          case watch::LeafKind::Expression: leaves[i] = evaluator.leaf(l); break;
        }
      }
      truths.push_back(program.evaluate(leaves.data(), stack.data()));
    }
  }
  return truths;
}

Found find_holding(Session& session, const watch::Program& program, std::span<const ModuleId> group,
                   SearchDirection direction, const Control& control) {
  return search(session, direction, [&](int64_t lo, int64_t hi) -> std::optional<std::optional<int64_t>> {
    const auto truths = truth_over(session, program, group, lo, hi, control);
    if (!truths) return std::nullopt;
    return nearest(direction, lo, hi,
                   [&](int64_t s) { return (*truths)[static_cast<size_t>(s - lo)] == watch::kTrue; });
  });
}

}  // namespace dw::sim
