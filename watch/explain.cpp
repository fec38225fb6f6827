#include "watch/explain.h"

#include <cstdlib>
#include <set>

#include "watch/detector.h"
#include "watch/parser.h"
#include "watch/windows.h"

namespace dw::watch {
namespace {

std::string offsets_text(const std::vector<int>& offsets) {
  std::string s;
  for (int o : offsets) s += (s.empty() ? "" : ", ") + std::to_string(o);
  return s;
}

// docs/design.md §4c: each window, how far back it looks and how it is evaluated.
void explain_windows(const watch::Watchpoint& w, std::ostream& out) {
  bool any = false;
  for (size_t i = 0; i < w.ast.nodes.size(); ++i) {
    const watch::Node& n = w.ast.nodes[i];
    if (n.kind != watch::NodeKind::Window) continue;
    if (!any)
      out << "  windows        (at each step a window keeps the shifts j whose reads fall at step 0 or later;"
          << " none kept: unknown)\n";
    any = true;
    if (n.window == watch::WindowKind::Since && n.value == 0) {
      out << "    " << watch::to_string(w.ast, static_cast<watch::NodeIndex>(i))
          << "\n      unbounded: each module keeps it as one bit a step, S(s) = psi(s) or (phi(s) and S(s - 1)), "
             "from the first step both can be read (cost independent of the past)\n";
      continue;
    }
    const int64_t reach = watch::window_reach(w.ast, static_cast<watch::NodeIndex>(i));
    out << "    " << watch::to_string(w.ast, static_cast<watch::NodeIndex>(i)) << "\n      j = 0.." << n.value
        << "; reach " << reach << (reach == 1 ? " step" : " steps") << " back (of the limit " << watch::kMaxOffset
        << "); ";
    if (watch::kept_by_module(w.ast, static_cast<watch::NodeIndex>(i)))
      out << "kept by each module from the step before and its condition now"
          << (n.window == watch::WindowKind::Times ? " (its count kept " + std::to_string(n.value + 1) + " steps)" : "")
          << " (cost per step independent of k)\n";
    else
      out << "evaluated as " << n.value + 1 << " shifted copies of its condition each step (cost O(k): it reads "
          << "neighbours, an aggregate, id() or more than one module)\n";
  }
}

// docs/design.md §4a, §7: what each reading finds and how long it takes to decide a watch step.
void explain_readings(const watch::Watchpoint& w, std::ostream& out) {
  const watch::Analysis& a = w.analysis;
  const watch::Program& p = w.program;
  if (p.slot_count() == 0) {  // docs/design.md §4c
    out << "  readings       (a watch step t is decided at step t + lag)\n"
        << "    every reading alike: the whole ensemble once a step, a fact of the engine's snapshot (no module, "
           "no PatternMatcher); --shape and --states change nothing; lag E+ = "
        << a.extent_plus << "\n";
    return;
  }
  const int k = p.slot_count();
  const int64_t e = a.extent_plus, h = a.aggregate_hops;
  using watch::GroupShape;
  const std::string hop = h == 0   ? ""
                          : h == 1 ? " + 1 (an aggregate's hop)"
                                   : " + " + std::to_string(h) + " (an aggregate's hops)";
  out << "  readings       (a watch step t is decided at step t + lag)\n";
  out << "    centralized: chain, ordered (default) or any groups, simultaneous states; lag E+ = " << e << "\n";
  out << "    distributed, consistent states (the paper's): chain groups only; lag E+ + k - 1" << hop << " = "
      << e + k - 1 + h << "\n";
  out << "    distributed, simultaneous states: latency L = k - 1 = " << watch::hop_latency(GroupShape::Chain, k)
      << " hops for chain, k(k - 1)/2 = " << watch::hop_latency(GroupShape::Any, k)
      << " for ordered and any; lag E+ + L" << hop << " = " << e + h + watch::hop_latency(GroupShape::Chain, k) << " / "
      << e + h + watch::hop_latency(GroupShape::Any, k) << "\n";
}

}  // namespace

void explain_watchpoint(const watch::Watchpoint& w, std::ostream& out) {
  const watch::Analysis& a = w.analysis;
  const watch::Program& p = w.program;
  out << "watchpoint " << w.name << " (" << w.source->name() << ")\n";
  out << "  normal form    " << watch::to_string(w.ast) << "\n";
  out << "  slots          " << p.slot_count() << ":";
  for (const auto& s : p.slot_names) out << " " << s;
  if (p.slot_count() == 0)
    out << " none, a zero-slot watchpoint on the whole ensemble (docs/design.md §4c): decided once a step, a match "
           "is the step itself with no module (\"slots\":{}); nothing to act on (no 'then')";
  out << "\n";
  out << "  E+             " << a.extent_plus
      << (a.extent_plus > 0 ? "  (looks ahead: detectors run " + std::to_string(a.extent_plus) +
                                  (a.extent_plus == 1 ? " step" : " steps") + " behind the ensemble)"
                            : "  (never looks ahead)")
      << "\n";
  out << "  variables" << (a.variables.empty() ? "      none" : "") << "\n";
  for (const watch::VariableUse& v : a.variables) {
    out << "    " << v.name << ": offsets " << offsets_text(v.offsets) << ", temporal span " << v.span()
        << ", history kept per module " << (a.extent_plus - v.min_offset() + 1)
        << (a.extent_plus - v.min_offset() == 0 ? " step" : " steps") << "\n";
  }
  out << "  slot reads\n";
  for (int s = 0; s < p.slot_count(); ++s) {
    out << "    " << p.slot_names[s] << ":";
    if (a.slot_reads[s].empty()) out << " nothing (a connector)";
    for (const watch::SlotRead& r : a.slot_reads[s]) {
      out << " " << a.variables[r.variable].name;
      if (r.offset) out << "@" << (r.offset > 0 ? "+" : "") << r.offset;
    }
    out << "\n";
  }
  out << "  neighbor()" << (a.neighbors.empty() ? "     none" : "") << "\n";
  for (const watch::NeighborConstraint& n : a.neighbors) {
    const std::string x = p.slot_names[n.x], y = p.slot_names[n.y];
    out << "    neighbor(" << x << " " << y << ") at offset " << n.offset << ": ";
    if (n.x < n.y) out << "culls candidates for " << y << " to N(" << x << "); " << x << " carries its neighbour set\n";
    else out << "decided by " << x << " from its own neighbour set (no culling)\n";
  }
  explain_windows(w, out);
  out << "  aggregates" << (a.aggregates.empty() ? "     none" : "") << "\n";
  std::set<uint32_t> shown;  // a window's copies of an aggregate are one aggregate as written
  for (const watch::AggregateUse& g : a.aggregates) {
    const watch::Node& n = w.ast.nodes[static_cast<size_t>(g.node)];
    if (!shown.insert(n.span.begin).second) continue;
    const std::string step =
        "now" + (g.offset ? (g.offset > 0 ? " + " : " - ") + std::to_string(std::abs(g.offset)) : std::string());
    out << "    " << watch::to_string(w.ast, g.node) << "\n      over ";
    if (g.domain == watch::Domain::All) out << "every module present at the match step (" << step << ")";
    else if (g.domain == watch::Domain::Component)
      out << "the connected cluster around " << p.slot_names[g.slot] << " of the modules where "
          << watch::to_string(w.ast, n.rhs) << " holds (breadth-first over N(·, " << step << "), "
          << p.slot_names[g.slot] << " first)";
    else if (g.domain == watch::Domain::Within)
      out << "the modules 1 to " << g.hops << " hops from " << p.slot_names[g.slot] << " (breadth-first over N(·, "
          << step << "), " << p.slot_names[g.slot] << " excluded)";
    else out << "N(" << p.slot_names[g.slot] << ", " << step << ")";
    if (!g.neighbor_reads.empty()) {
      out << "; reads of each neighbour " << n.name << ":";
      for (const watch::SlotRead& r : g.neighbor_reads)
        out << " " << a.variables[r.variable].name
            << (r.offset ? "@" + std::string(r.offset > 0 ? "+" : "") + std::to_string(r.offset) : "");
    }
    if (!g.neighbor_sets.empty()) out << "; its neighbours' own neighbour sets";
    if (!g.slots.empty()) {
      out << "; slots read inside:";
      for (int s : g.slots) out << " " << p.slot_names[s];
    }
    out << "\n      distributed: ";
    if (g.domain == watch::Domain::All || g.domain == watch::Domain::Component)
      out << "a fact of the engine's snapshot of the step (one record a module read), no lag";
    else if (g.domain == watch::Domain::Within)
      out << "learnt by " << g.hops << " rounds of messages: +" << g.hops << " to the distributed lags";
    else
      out << (g.needs_messages() ? "the neighbours' values come by message, one hop: +1 to the distributed lags"
                                 : "decided from the module's own neighbour set, no message");
    out << "\n";
  }
  explain_readings(w, out);
  if (!w.ast.actions.empty()) {
    out << "  actions        (a match at t acts at the start of step t + lag + 1, with the match's reading)\n";
    for (const watch::Action& act : w.ast.actions) {
      out << "    "
          << (act.kind == watch::Action::Kind::Remove
                  ? "remove " + p.slot_names[act.slot]
                  : "set " + p.slot_names[act.slot] + "." + act.variable + " = " + watch::to_string(w.ast, act.value))
          << "\n";
    }
  }
  out << "  PatternMatcher " << p.leaves.size() << " leaves, " << p.cells.size() << " carried value(s), "
      << p.sets.size() << " carried neighbour set(s)\n";
}

}  // namespace dw::watch
