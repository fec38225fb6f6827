#include "watch/analysis.h"

#include <algorithm>

namespace dw::watch {
namespace {

template <class T, class Less, class Equal>
void sort_unique(std::vector<T>& v, Less less, Equal equal) {
  std::sort(v.begin(), v.end(), less);
  v.erase(std::unique(v.begin(), v.end(), equal), v.end());
}

void sort_unique_reads(std::vector<SlotRead>& reads) {
  sort_unique(
      reads,
      [](const SlotRead& l, const SlotRead& r) {
        return l.variable != r.variable ? l.variable < r.variable : l.offset < r.offset;
      },
      [](const SlotRead& l, const SlotRead& r) { return l.variable == r.variable && l.offset == r.offset; });
}

}  // namespace

int Analysis::variable_index(const std::string& name) const {
  for (size_t i = 0; i < variables.size(); ++i)
    if (variables[i].name == name) return static_cast<int>(i);
  return -1;
}

Analysis analyze(const Ast& ast) {
  Analysis a;
  a.slot_reads.resize(ast.slots.size());
  auto offset_seen = [&](int offset) {
    a.extent_plus = std::max(a.extent_plus, offset);
    a.min_offset = std::min(a.min_offset, offset);
  };
  auto graph_read = [&](int offset) {
    offset_seen(offset);
    a.min_neighbor_offset = std::min(a.min_neighbor_offset, offset);
  };
  auto variable = [&](const std::string& name, int offset) {
    int v = a.variable_index(name);
    if (v < 0) {
      v = static_cast<int>(a.variables.size());
      a.variables.push_back({name, {}});
    }
    a.variables[v].offsets.push_back(offset);
    offset_seen(offset);
    return v;
  };
  std::vector<int> aggregate_of(ast.nodes.size(), -1);  // node -> index into a.aggregates
  auto visit = [&](NodeIndex i, NodeIndex in) {
    const Node& n = ast.nodes[static_cast<size_t>(i)];
    AggregateUse* agg = in == kNoNode ? nullptr : &a.aggregates[static_cast<size_t>(aggregate_of[in])];
    // A bound name's offset counts from the aggregate's step: its module's offset.
    auto absolute = [&](const ModuleRef& m) { return m.bound ? agg->offset + m.offset : m.offset; };
    auto mentions = [&](const ModuleRef& m) {
      if (agg != nullptr && !m.bound && m.slot != agg->slot) agg->slots.push_back(m.slot);
    };
    switch (n.kind) {
      case NodeKind::Aggregate:
        aggregate_of[i] = static_cast<int>(a.aggregates.size());
        a.aggregates.push_back({i, n.x.slot, n.x.offset, n.domain, static_cast<int>(n.value), {}, {}, {}});
        graph_read(n.x.offset);
        break;
      case NodeKind::Variable: {
        const int v = variable(n.name, absolute(n.x));
        if (n.x.bound) agg->neighbor_reads.push_back({v, n.x.offset});
        else a.slot_reads[n.x.slot].push_back({v, n.x.offset});
        mentions(n.x);
        break;
      }
      case NodeKind::KeptWindow:  // a bit its module keeps (its conditions, below, are read to work it out)
        offset_seen(n.x.offset);
        mentions(n.x);
        break;
      case NodeKind::Id:  // the module's presence, kept with its neighbour set
        graph_read(absolute(n.x));
        mentions(n.x);
        break;
      case NodeKind::Neighbor:
        graph_read(absolute(n.x));
        if (n.x.bound) agg->neighbor_sets.push_back(n.x.offset);
        mentions(n.x);
        mentions(n.y);
        if (agg == nullptr) a.neighbors.push_back({n.x.slot, n.y.slot, n.x.offset, i});
        break;
      default: break;
    }
  };
  if (ast.root != kNoNode) visit_tree(ast, evaluated_root(ast), visit);
  for (const Action& act : ast.actions)
    if (act.kind == Action::Kind::Set) visit_tree(ast, evaluated_value(act), visit);
  for (VariableUse& v : a.variables) sort_unique(v.offsets, std::less<int>{}, std::equal_to<int>{});
  for (auto& reads : a.slot_reads) sort_unique_reads(reads);
  for (AggregateUse& g : a.aggregates) {
    sort_unique_reads(g.neighbor_reads);
    sort_unique(g.neighbor_sets, std::less<int>{}, std::equal_to<int>{});
    sort_unique(g.slots, std::less<int>{}, std::equal_to<int>{});
    a.aggregate_hops = std::max(a.aggregate_hops, g.lag());
  }
  return a;
}

}  // namespace dw::watch
