#include "app/explain.h"

namespace dw::app {
namespace {

std::string offsets_text(const std::vector<int>& offsets) {
  std::string s;
  for (int o : offsets) s += (s.empty() ? "" : ", ") + std::to_string(o);
  return s;
}

}  // namespace

void explain_watchpoint(const watch::Watchpoint& w, std::ostream& out) {
  const watch::Analysis& a = w.analysis;
  const watch::Program& p = w.program;
  out << "watchpoint " << w.name << " (" << w.source->name() << ")\n";
  out << "  normal form    " << watch::to_string(w.ast) << "\n";
  out << "  slots          " << p.slot_count() << ":";
  for (const auto& s : p.slot_names) out << " " << s;
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
  out << "  PatternMatcher " << p.leaves.size() << " leaves, " << p.cells.size() << " carried value(s), "
      << p.sets.size() << " carried neighbour set(s)\n";
}

}  // namespace dw::app
