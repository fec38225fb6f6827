// Recording a window of the session's history for `why` (docs/design.md §7b): the cursor walks the
// window a step at a time (each step re-simulated once, from the keyframe before the window) and
// goes back where it was; what each state holds for the next step (its inbox, the actions due,
// the modules moving) becomes that step's record.
#include "sim/causal_history.h"

#include <algorithm>

#include "sim/session.h"

namespace dw::sim {

const MovingModule* StepRecord::mover(ModuleId m) const {
  const auto at = std::lower_bound(moving.begin(), moving.end(), m,
                                   [](const MovingModule& x, ModuleId id) { return x.module < id; });
  return at != moving.end() && at->module == m ? &*at : nullptr;
}

void StepRecord::index_reads(uint32_t modules) {
  read_begin.assign(size_t{modules} + 1, 0);
  for (const ReadMessage& m : read) ++read_begin[size_t{m.to} + 1];
  for (uint32_t i = 0; i < modules; ++i) read_begin[i + 1] += read_begin[i];
}

int64_t CausalHistory::value_read(int64_t s, ModuleId m, int column) const {
  int64_t v = value(s - 1, m, column);
  if (holds(s))
    for (const OutsideWrite& w : at(s).outside)
      if (w.module == m && w.column == column && !w.remove) v = w.value;
  return v;
}

std::optional<int64_t> origin_step(Session& session, ModuleId m, int column, int64_t t, const Control& control) {
  // Most values changed lately: a short window first, then each window before the last, four times
  // longer, ending at its first step (so no step is simulated twice but for the keyframe's lead-in).
  int64_t to = t;
  for (int64_t span = 16;; span *= 4) {
    const int64_t from = std::max<int64_t>(0, to - span);
    std::vector<uint8_t> present;
    const auto values = session.series(m, column, from, to, control, &present);
    // Without history the past cannot be simulated again: nothing comes back.
    if (!values || values->size() != static_cast<size_t>(to - from + 1)) return std::nullopt;
    for (int64_t w = to; w > from; --w) {
      const auto i = static_cast<size_t>(w - from);
      if (present[i] && (!present[i - 1] || (*values)[i] != (*values)[i - 1])) return w;
    }
    if (from == 0) return 0;
    to = from;
  }
}

namespace {

// What a state after step t - 1 holds for step t: the messages read at t, the actions due at its
// start and the modules moving as N(·, t) was measured.
void take_next(Session& session, const State& state, StepRecord& rec) {
  const int64_t t = state.step;
  // Each message's words, stored once per sender and program while it sends the same (a
  // broadcast's copies share them): a step's messages are megabytes at 10,000 modules, and
  // copied whole they were most of a `why` (fresh pages to fault in).
  const Messages inbox = state.inbox.messages.all();
  size_t words = 0;
  for (const Message m : inbox) words += m.size;
  rec.read.reserve(inbox.size());
  rec.words.reserve(words);  // pages never written are never faulted in
  // Per sender and program: its last message read (the inbox is grouped by receiver, then program).
  const uint32_t programs = session.model().program_count();
  std::vector<uint32_t> last(size_t{session.model().module_count()} * programs, UINT32_MAX);
  for (const Message m : inbox) {
    uint32_t first = static_cast<uint32_t>(rec.words.size());
    uint32_t& l = last[size_t{m.from} * programs + m.program];
    if (l != UINT32_MAX && rec.read[l].size == m.size &&
        std::equal(m.words, m.words + m.size, rec.words.data() + rec.read[l].first))
      first = rec.read[l].first;
    else rec.words.insert(rec.words.end(), m.words, m.words + m.size);
    l = static_cast<uint32_t>(rec.read.size());
    rec.read.push_back({m.from, m.to, t - 1, first, m.size});
  }
  for (const PendingAction& a : state.actions) {
    if (!a.remove && !(a.known && a.column >= 0)) continue;  // skipped: it writes nothing
    OutsideWrite w{.by = OutsideWrite::By::Action,
                   .module = a.module,
                   .column = a.remove ? -1 : a.column,
                   .value = a.value,
                   .remove = a.remove,
                   .watch = a.watch};
    // Its match: one found during step t - 1 whose group holds the module.
    const MatchList& list = session.matches(a.watch);
    const size_t k = session.watches()[a.watch].hosted.watchpoint.program.slot_count();
    for (size_t i = 0; i < list.size() && w.match_t < 0; ++i) {
      if (list.detected[i] != t - 1) continue;
      const auto group = std::span(list.slots).subspan(i * k, k);
      if (std::find(group.begin(), group.end(), a.module) == group.end()) continue;
      w.match_t = list.t[i];
      w.match_group.assign(group.begin(), group.end());
    }
    rec.outside.push_back(std::move(w));
  }
  for (const Mover& m : state.bodies.movers) rec.moving.push_back({m.module, m.start, m.axis != Vec3{}});
}

}  // namespace

std::optional<CausalHistory> record_window(Session& session, int64_t first, int64_t last, const Control& control,
                                           Recording recording) {
  const bool causes = recording == Recording::Causes;
  if (first < 0 || first > last || last > session.latest() || !session.has_history()) return std::nullopt;
  const int64_t back = session.current();
  const Model& model = session.model();
  CausalHistory h;
  h.modules = model.module_count();
  h.variables = model.variable_count();
  h.first = first;
  if (!session.seek(first - 1, control)) return std::nullopt;
  StepRecord next;
  {
    const State& s = session.state();
    h.before = s.values;
    if (causes) take_next(session, s, next);
  }
  // Each step of the window reported as done of the window's steps (a deep cone over many modules
  // takes seconds); the one-step seeks within it report nothing of their own.
  const Control step_control{.stop = control.stop};
  for (int64_t t = first; t <= last; ++t) {
    StepRecord rec = std::move(next);
    next = StepRecord{};
    rec.step = t;
    // The interventions come after the actions, as the runtime carries them out.
    for (const Intervention& i : session.interventions()) {
      if (i.at != t || !causes) continue;
      rec.outside.push_back({.by = i.scheduled ? OutsideWrite::By::Event : OutsideWrite::By::Intervention,
                             .module = i.module,
                             .column = i.kind == Intervention::Kind::Set ? i.column : -1,
                             .value = i.value,
                             .remove = i.kind == Intervention::Kind::Remove});
    }
    if (!session.seek(t, step_control)) {
      session.seek(back);
      return std::nullopt;
    }
    if (control.progress) control.progress(t - first + 1, last - first + 1);
    const State& s = session.state();
    rec.values = s.values;
    const std::span<const uint8_t> present = session.seen_present();
    rec.present.assign(present.begin(), present.end());
    rec.graph = std::make_shared<const NeighborGraph>(session.seen_graph());
    if (t < last && causes) take_next(session, s, next);
    if (causes) rec.index_reads(h.modules);
    h.steps.push_back(std::move(rec));
  }
  session.seek(back);
  return h;
}

}  // namespace dw::sim
