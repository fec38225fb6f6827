#include "watch/program.h"

#include <algorithm>

namespace dw::watch {

namespace {

class Compiler {
 public:
  Compiler(const Ast& ast, const Analysis& analysis, Program& p) : ast_(ast), analysis_(analysis), p_(p) {}

  void run() {
    for (const SlotDecl& s : ast_.slots) p_.slot_names.push_back(s.name);
    for (const VariableUse& v : analysis_.variables) {
      p_.variables.push_back(v.name);
      p_.variable_min_offset.push_back(v.min_offset());
    }
    p_.extent_plus = analysis_.extent_plus;
    p_.min_offset = analysis_.min_offset;
    p_.min_neighbor_offset = analysis_.min_neighbor_offset;
    p_.slots.resize(ast_.slots.size());
    emit_postfix();
    p_.leaf_count = static_cast<uint32_t>(p_.leaves.size());
    const bool conjunction = std::all_of(p_.expr.begin(), p_.expr.end(), [](const ExprOp& op) {
      return op.kind == ExprOp::PushLeaf || op.kind == ExprOp::And;
    });
    p_.shape = conjunction ? Program::Shape::Conjunction : Program::Shape::General;
    // Carried sets must be ordered by slot, because a PatternMatcher appends them as it fills.
    std::vector<uint16_t> order(p_.sets.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<uint16_t>(i);
    std::stable_sort(order.begin(), order.end(),
                     [&](uint16_t a, uint16_t b) { return p_.sets[a].slot < p_.sets[b].slot; });
    std::vector<int16_t> renumber(order.size());
    std::vector<CarriedSet> sorted;
    for (size_t i = 0; i < order.size(); ++i) {
      renumber[order[i]] = static_cast<int16_t>(i);
      sorted.push_back(p_.sets[order[i]]);
    }
    p_.sets = std::move(sorted);
    for (Leaf& l : p_.leaves)
      if (l.set >= 0) l.set = renumber[l.set];
    for (size_t i = 0; i < p_.sets.size(); ++i) p_.slots[p_.sets[i].slot].sets.push_back(static_cast<uint16_t>(i));
  }

 private:
  // Postfix code in an explicit stack walk: the tree may be thousands of nodes deep.
  void emit_postfix() {
    struct Item {
      NodeIndex node;
      bool expanded;
    };
    std::vector<Item> work{{ast_.root, false}};
    int depth = 0;
    while (!work.empty()) {
      Item it = work.back();
      work.pop_back();
      const Node& n = ast_.nodes[it.node];
      if (n.kind == NodeKind::Compare || n.kind == NodeKind::Neighbor) {
        p_.expr.push_back({ExprOp::PushLeaf, compile_leaf(it.node)});
        p_.max_stack = std::max(p_.max_stack, ++depth);
        continue;
      }
      if (it.expanded) {
        if (n.kind == NodeKind::Not) {
          p_.expr.push_back({ExprOp::Not, 0});
        } else {
          p_.expr.push_back({n.kind == NodeKind::And ? ExprOp::And : ExprOp::Or, 0});
          --depth;
        }
        continue;
      }
      work.push_back({it.node, true});
      if (n.kind != NodeKind::Not) work.push_back({n.rhs, false});
      work.push_back({n.lhs, false});
    }
  }

  TermRef term(const Operand& o) {
    TermRef t;
    t.slot = static_cast<int16_t>(o.module.slot);
    t.variable = static_cast<int16_t>(analysis_.variable_index(o.variable));
    t.offset = static_cast<int16_t>(o.module.offset);
    return t;
  }

  // A term read before the leaf's decide slot is carried in a cell (shared between leaves).
  void carry(TermRef& t, int decide_slot) {
    if (t.slot == decide_slot) return;
    for (size_t i = 0; i < p_.cells.size(); ++i) {
      const CarriedCell& c = p_.cells[i];
      if (c.slot == t.slot && c.variable == t.variable && c.offset == t.offset) {
        t.cell = static_cast<int16_t>(i);
        return;
      }
    }
    t.cell = static_cast<int16_t>(p_.cells.size());
    p_.cells.push_back({t.slot, t.variable, t.offset});
    p_.slots[t.slot].cells.push_back(static_cast<uint16_t>(t.cell));
  }

  uint32_t compile_leaf(NodeIndex i) {
    const Node& n = ast_.nodes[i];
    Leaf l;
    l.node = i;
    if (n.kind == NodeKind::Compare) {
      l.kind = LeafKind::Compare;
      l.op = n.op;
      l.lhs = term(n.left);
      l.decide_slot = l.lhs.slot;
      if (n.right.is_constant) {
        l.rhs_is_constant = true;
        l.constant = n.right.constant;
      } else {
        l.rhs = term(n.right);
        l.decide_slot = std::max(l.decide_slot, l.rhs.slot);
      }
      carry(l.lhs, l.decide_slot);
      if (!l.rhs_is_constant) carry(l.rhs, l.decide_slot);
    } else {
      l.kind = LeafKind::Neighbor;
      l.x = static_cast<int16_t>(n.x.slot);
      l.y = static_cast<int16_t>(n.y.slot);
      l.offset = static_cast<int16_t>(n.x.offset);
      l.decide_slot = std::max(l.x, l.y);
      if (l.x < l.y) {
        for (size_t s = 0; s < p_.sets.size(); ++s)
          if (p_.sets[s].slot == l.x && p_.sets[s].offset == l.offset) l.set = static_cast<int16_t>(s);
        if (l.set < 0) {
          l.set = static_cast<int16_t>(p_.sets.size());
          p_.sets.push_back({l.x, l.offset});
        }
      }
    }
    const uint32_t index = static_cast<uint32_t>(p_.leaves.size());
    SlotProgram& decider = p_.slots[l.decide_slot];
    decider.leaves.push_back(static_cast<uint16_t>(index));
    const bool own = l.kind == LeafKind::Compare && l.lhs.cell < 0 && (l.rhs_is_constant || l.rhs.cell < 0);
    (own ? decider.own_leaves : decider.carried_leaves).push_back(static_cast<uint16_t>(index));
    if (l.kind == LeafKind::Neighbor && l.x < l.y) p_.slots[l.y].cull_leaves.push_back(static_cast<uint16_t>(index));
    p_.leaves.push_back(l);
    return index;
  }

  const Ast& ast_;
  const Analysis& analysis_;
  Program& p_;
};

}  // namespace

Program::Program(const Ast& ast, const Analysis& analysis) { Compiler(ast, analysis, *this).run(); }

}  // namespace dw::watch
