#include "watch/analysis.h"

#include <algorithm>

namespace dw::watch {

int Analysis::variable_index(const std::string& name) const {
  for (size_t i = 0; i < variables.size(); ++i)
    if (variables[i].name == name) return static_cast<int>(i);
  return -1;
}

Analysis analyze(const Ast& ast) {
  Analysis a;
  a.slot_reads.resize(ast.slots.size());
  auto use = [&](const Operand& o) {
    if (o.is_constant) return;
    int v = a.variable_index(o.variable);
    if (v < 0) {
      v = static_cast<int>(a.variables.size());
      a.variables.push_back({o.variable, {}});
    }
    a.variables[v].offsets.push_back(o.module.offset);
    a.slot_reads[o.module.slot].push_back({v, o.module.offset});
    a.extent_plus = std::max(a.extent_plus, o.module.offset);
    a.min_offset = std::min(a.min_offset, o.module.offset);
  };
  // Nodes are stored children-first, so a plain scan visits every term without recursion.
  for (NodeIndex i = 0; i < static_cast<NodeIndex>(ast.nodes.size()); ++i) {
    const Node& n = ast.nodes[i];
    if (n.kind == NodeKind::Compare) {
      use(n.left);
      use(n.right);
    } else if (n.kind == NodeKind::Neighbor) {
      a.neighbors.push_back({n.x.slot, n.y.slot, n.x.offset, i});
      a.extent_plus = std::max(a.extent_plus, n.x.offset);
      a.min_offset = std::min(a.min_offset, n.x.offset);
      a.min_neighbor_offset = std::min(a.min_neighbor_offset, n.x.offset);
    }
  }
  for (VariableUse& v : a.variables) {
    std::sort(v.offsets.begin(), v.offsets.end());
    v.offsets.erase(std::unique(v.offsets.begin(), v.offsets.end()), v.offsets.end());
  }
  for (auto& reads : a.slot_reads) {
    std::sort(reads.begin(), reads.end(), [](const SlotRead& l, const SlotRead& r) {
      return l.variable != r.variable ? l.variable < r.variable : l.offset < r.offset;
    });
    reads.erase(std::unique(reads.begin(), reads.end(),
                            [](const SlotRead& l, const SlotRead& r) {
                              return l.variable == r.variable && l.offset == r.offset;
                            }),
                reads.end());
  }
  return a;
}

}  // namespace dw::watch
