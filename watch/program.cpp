#include "watch/program.h"

#include <algorithm>
#include <map>

#include "watch/windows.h"

namespace dw::watch {

namespace {

CompareOp mirrored(CompareOp op) {
  switch (op) {
    case CompareOp::Less: return CompareOp::Greater;
    case CompareOp::Greater: return CompareOp::Less;
    case CompareOp::GreaterEqual: return CompareOp::LessEqual;
    case CompareOp::LessEqual: return CompareOp::GreaterEqual;
    default: return op;
  }
}

ValueOp value_op(NodeKind k) {
  switch (k) {
    case NodeKind::Negate: return ValueOp::Negate;
    case NodeKind::Add: return ValueOp::Add;
    case NodeKind::Subtract: return ValueOp::Subtract;
    case NodeKind::Multiply: return ValueOp::Multiply;
    case NodeKind::Divide: return ValueOp::Divide;
    case NodeKind::Remainder: return ValueOp::Remainder;
    case NodeKind::Abs: return ValueOp::Abs;
    case NodeKind::Min: return ValueOp::Min;
    default: return ValueOp::Max;
  }
}

// Walks the tree under `root` in postfix order without recursion (trees may be thousands deep):
// leaf(node) where is_leaf(node), op(node) for an operator once its operands are done (one operand
// for not, negation and abs; two for the others). Returns the deepest operand stack the order needs.
template <class IsLeaf, class Leaf, class Op>
int postfix(const Ast& ast, NodeIndex root, IsLeaf&& is_leaf, Leaf&& leaf, Op&& op) {
  struct Item {
    NodeIndex node;
    bool expanded;
  };
  std::vector<Item> work{{root, false}};
  int depth = 0, deepest = 0;
  while (!work.empty()) {
    const Item it = work.back();
    work.pop_back();
    const Node& n = ast.nodes[static_cast<size_t>(it.node)];
    const bool unary = n.kind == NodeKind::Not || n.kind == NodeKind::Negate || n.kind == NodeKind::Abs;
    if (is_leaf(n)) {
      leaf(it.node);
      deepest = std::max(deepest, ++depth);
    } else if (it.expanded) {
      op(n);
      if (!unary) --depth;
    } else {
      work.push_back({it.node, true});
      if (!unary) work.push_back({n.rhs, false});
      work.push_back({n.lhs, false});
    }
  }
  return deepest;
}

bool is_test(const Node& n) { return n.kind == NodeKind::Compare || n.kind == NodeKind::Neighbor; }

ExprOp::Kind logic_op(NodeKind k) {
  return k == NodeKind::Not ? ExprOp::Not : k == NodeKind::And ? ExprOp::And : ExprOp::Or;
}

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
    p_.aggregate_hops = analysis_.aggregate_hops;
    p_.min_offset = analysis_.min_offset;
    p_.min_neighbor_offset = analysis_.min_neighbor_offset;
    p_.slots.resize(ast_.slots.size());
    emit_postfix();
    p_.leaf_count = static_cast<uint32_t>(p_.leaves.size());
    const bool conjunction = std::all_of(p_.expr.begin(), p_.expr.end(), [](const ExprOp& op) {
      return op.kind == ExprOp::PushLeaf || op.kind == ExprOp::And;
    });
    p_.shape = conjunction ? Program::Shape::Conjunction : Program::Shape::General;
    // Actions are decided with the match, at the last slot (docs/design.md §4b).
    for (const Action& a : ast_.actions) {
      ActionCode code{a.kind, static_cast<int16_t>(a.slot), a.variable, kNoCode};
      if (a.kind == Action::Kind::Set) {
        decide_ = static_cast<int16_t>(p_.slot_count() - 1);
        code.value = compile_value(evaluated_value(a));
      }
      p_.actions.push_back(std::move(code));
    }
    order_sets();
    keep_window_columns();
    keep_wider_domains();
  }

 private:
  // Carried sets and tables must be ordered by slot, because a PatternMatcher appends them as it
  // fills; what refers to them is renumbered.
  void order_sets() {
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
    for (ConditionTest& t : p_.tests)
      if (t.set >= 0) t.set = renumber[t.set];
    for (AggregateCode& a : p_.aggregates)
      if (a.table >= 0) a.table = renumber[a.table];
    for (size_t i = 0; i < p_.sets.size(); ++i) p_.slots[p_.sets[i].slot].sets.push_back(static_cast<uint16_t>(i));
  }

  // The expression as postfix code over its leaves.
  void emit_postfix() {
    p_.max_stack = std::max(1, postfix(
                                   ast_, evaluated_root(ast_), is_test,
                                   [&](NodeIndex i) {
                                     p_.expr.push_back({ExprOp::PushLeaf, compile_leaf(i)});
                                   },
                                   [&](const Node& n) {
                                     p_.expr.push_back({logic_op(n.kind), 0});
                                   }));
  }

  // A variable, id() or a kept window's value (a column of its own) as a slot reads it.
  TermRef term(const Node& v) {
    TermRef t;
    t.slot = static_cast<int16_t>(v.x.slot);
    if (v.kind == NodeKind::KeptWindow) t.variable = kept_column(v);
    else t.variable = v.kind == NodeKind::Id ? kIdVariable : static_cast<int16_t>(analysis_.variable_index(v.name));
    t.offset = static_cast<int16_t>(v.x.offset);
    return t;
  }

  // A term read before the leaf's decide slot is carried in a cell (shared between leaves).
  void carry(TermRef& t, int decide_slot) {
    if (t.slot == decide_slot) return;
    carries_ = true;
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

  // N(slot, now + offset), carried by the slot's module when it fills before the decide slot.
  int16_t carried_set(int16_t slot, int16_t offset) {
    carries_ = true;
    for (size_t s = 0; s < p_.sets.size(); ++s)
      if (p_.sets[s].slot == slot && p_.sets[s].offset == offset && p_.sets[s].aggregate < 0)
        return static_cast<int16_t>(s);
    p_.sets.push_back({slot, offset, -1});
    return static_cast<int16_t>(p_.sets.size() - 1);
  }

  // The slot every term of `node` reads that fills last (0 when it reads none).
  int16_t last_slot(NodeIndex node) const {
    int16_t last = 0;
    visit_tree(ast_, node, [&](NodeIndex i, NodeIndex) {
      const Node& n = ast_.nodes[i];
      if (n.kind == NodeKind::Variable || n.kind == NodeKind::Id || n.kind == NodeKind::Aggregate ||
          n.kind == NodeKind::Neighbor || n.kind == NodeKind::KeptWindow)
        for (const ModuleRef* m : {&n.x, &n.y})
          if (!m->bound && m->slot >= 0 && (n.kind == NodeKind::Neighbor || m == &n.x))
            last = std::max(last, static_cast<int16_t>(m->slot));
    });
    return last;
  }

  uint32_t compile_leaf(NodeIndex i) {
    const Node& n = ast_.nodes[i];
    Leaf l;
    l.node = i;
    carries_ = false;
    if (n.kind == NodeKind::Neighbor) {
      l.kind = LeafKind::Neighbor;
      l.x = static_cast<int16_t>(n.x.slot);
      l.y = static_cast<int16_t>(n.y.slot);
      l.offset = static_cast<int16_t>(n.x.offset);
      l.decide_slot = std::max(l.x, l.y);
      if (l.x < l.y) l.set = carried_set(l.x, l.offset);
    } else {
      const Node* left = &ast_.nodes[n.lhs];
      const Node* right = &ast_.nodes[n.rhs];
      l.op = n.op;
      // A slot's variable or kept window (watch/kept_windows.h): a column the readings compare whole.
      auto column = [](const Node* o) {
        return (o->kind == NodeKind::Variable && !o->x.bound) || o->kind == NodeKind::KeptWindow;
      };
      auto plain = [&](const Node* o) { return o->kind == NodeKind::Integer || column(o); };
      if (left->kind == NodeKind::Integer && column(right)) {
        std::swap(left, right);  // `1 < a.x` is `a.x > 1`
        l.op = mirrored(l.op);
      }
      if (column(left) && plain(right)) {
        l.kind = LeafKind::Compare;
        l.lhs = term(*left);
        l.decide_slot = l.lhs.slot;
        if (right->kind == NodeKind::Integer) {
          l.rhs_is_constant = true;
          l.constant = right->value;
        } else {
          l.rhs = term(*right);
          l.decide_slot = std::max(l.decide_slot, l.rhs.slot);
        }
        carry(l.lhs, l.decide_slot);
        if (!l.rhs_is_constant) carry(l.rhs, l.decide_slot);
      } else {
        l.kind = LeafKind::Expression;
        l.decide_slot = std::max(last_slot(n.lhs), last_slot(n.rhs));
        decide_ = l.decide_slot;
        l.lhs_code = compile_value(n.lhs);
        l.rhs_code = compile_value(n.rhs);
      }
    }
    const uint32_t index = static_cast<uint32_t>(p_.leaves.size());
    p_.leaves.push_back(l);
    // A zero-slot watchpoint (docs/design.md §4c) has no slot to decide its leaves at: it is
    // decided whole, once a step (watch/ensemble_detector.h).
    if (p_.slots.empty()) return index;
    SlotProgram& decider = p_.slots[l.decide_slot];
    decider.leaves.push_back(static_cast<uint16_t>(index));
    const bool own = l.kind != LeafKind::Neighbor && !carries_;
    (own ? decider.own_leaves : decider.carried_leaves).push_back(static_cast<uint16_t>(index));
    if (l.kind == LeafKind::Neighbor && l.x < l.y) p_.slots[l.y].cull_leaves.push_back(static_cast<uint16_t>(index));
    return index;
  }

  // A condition read as an integer (Program::truths); the ones inside it are compiled first.
  uint32_t compile_truth(NodeIndex condition) {
    int depth = 0;
    std::vector<ExprOp> ops = compile_condition(condition, aggregate_, depth);
    p_.truths.push_back(std::move(ops));
    p_.truth_depths.push_back(depth);
    return static_cast<uint32_t>(p_.truths.size() - 1);
  }

  // The column that holds the value of the kept window `n` stands for (watch/kept_windows.h): made
  // the first time, with its conditions compiled as its slot's own (nothing carried).
  int16_t kept_column(const Node& n) {
    const NodeIndex written = static_cast<NodeIndex>(n.value);
    auto found = kept_index_.find(written);
    if (found == kept_index_.end()) {
      const Node& window = ast_.nodes[static_cast<size_t>(written)];
      KeptWindow w;
      w.kind = window.window;
      w.k = static_cast<int>(window.value);
      w.slot = static_cast<int16_t>(n.x.slot);
      const KeptSteps steps = kept_steps(ast_, written);
      w.first_step = steps.first_step;
      w.ahead = steps.ahead;
      const int16_t decide = decide_;
      const bool carries = carries_;
      decide_ = w.slot;
      // A window inside this one gets its columns first: histories work them out in order.
      w.phi = compile_truth(n.lhs);
      if (n.rhs != kNoNode) w.psi = compile_truth(n.rhs);
      decide_ = decide;
      carries_ = carries;
      w.column = static_cast<int>(p_.variables.size()) + p_.kept_columns;
      p_.kept_columns += w.columns();
      found = kept_index_.emplace(written, p_.kept_windows.size()).first;
      p_.kept_windows.push_back(w);
      kept_read_offset_.push_back(n.x.offset);
    }
    kept_read_offset_[found->second] = std::min(kept_read_offset_[found->second], n.x.offset);
    return static_cast<int16_t>(p_.kept_windows[found->second].column);
  }

  // Of each kept window's columns, how far back it is kept (docs/design.md §4c): its value from its
  // earliest read, and what working out step s reads from the step before (the value of an
  // unbounded since, each state column), or, of times' count, from step s − k − 1; each known
  // once step s + ahead is.
  void keep_window_columns() {
    for (size_t i = 0; i < p_.kept_windows.size(); ++i) {
      const KeptWindow& w = p_.kept_windows[i];
      const int at_s = p_.extent_plus - w.ahead;  // step s, as an offset of the detector's step
      for (int c = 0; c < w.columns(); ++c) {
        int back = 1;
        if (c == 0 && w.k > 0) back = 0;
        if (c == 1 && w.kind == WindowKind::Times) back = w.k + 1;
        p_.variable_min_offset.push_back(std::min(c == 0 ? kept_read_offset_[i] : at_s, at_s - back));
      }
    }
  }

  // within(), all and component() are read where their leaf is decided, from the history of every
  // module: in the distributed reading up to k - 1 steps after their own slot's step. Their reads
  // are kept that much longer (what a table carries for neighbors(), they read again).
  void keep_wider_domains() {
    const int later = std::max(0, p_.slot_count() - 1);
    for (const AggregateCode& a : p_.aggregates) {
      if (a.domain == Domain::Neighbors) continue;
      p_.min_neighbor_offset = std::min(p_.min_neighbor_offset, a.offset - later);
      for (const TermRef& r : a.neighbor_reads) {
        if (r.variable == kIdVariable) {
          p_.min_neighbor_offset = std::min(p_.min_neighbor_offset, a.offset + r.offset - later);
          continue;
        }
        int& kept = p_.variable_min_offset[static_cast<size_t>(r.variable)];
        kept = std::min(kept, a.offset + r.offset - later);
      }
      for (int16_t o : a.neighbor_sets) p_.min_neighbor_offset = std::min(p_.min_neighbor_offset, a.offset + o - later);
    }
  }

  // An integer expression as postfix value code, its terms carried as decide_ requires.
  uint32_t compile_value(NodeIndex root) {
    std::vector<ValueInstr> code;
    auto is_operand = [](const Node& n) {
      return n.kind == NodeKind::Integer || n.kind == NodeKind::Variable || n.kind == NodeKind::Aggregate ||
             n.kind == NodeKind::Id || n.kind == NodeKind::Step || n.kind == NodeKind::Truth ||
             n.kind == NodeKind::KeptWindow;
    };
    auto operand = [&](NodeIndex i) {
      const Node& n = ast_.nodes[i];
      ValueInstr in;
      if (n.kind == NodeKind::Id) p_.reads_id = true;
      if (n.kind == NodeKind::Integer) {
        in.op = ValueOp::Constant;
        in.constant = n.value;
      } else if (n.kind == NodeKind::KeptWindow) {
        TermRef t = term(n);
        carry(t, decide_);
        in.op = ValueOp::Term;
        in.slot = t.slot;
        in.variable = t.variable;
        in.offset = t.offset;
        in.cell = t.cell;
      } else if (n.kind == NodeKind::Step) {
        in.op = ValueOp::Step;
        in.slot = static_cast<int16_t>(n.x.slot);
        in.offset = static_cast<int16_t>(n.x.offset);
      } else if (n.kind == NodeKind::Truth) {
        in.op = ValueOp::Truth;
        in.index = compile_truth(n.lhs);
      } else if (n.kind == NodeKind::Aggregate) {
        in.op = ValueOp::Aggregate;
        in.index = compile_aggregate(i);
      } else if (n.x.bound) {
        const TermRef t = term(n);
        in.op = ValueOp::Bound;
        in.variable = t.variable;
        in.offset = t.offset;
        std::vector<TermRef>& reads = p_.aggregates[aggregate_].neighbor_reads;
        if (std::none_of(reads.begin(), reads.end(),
                         [&](const TermRef& r) { return r.variable == t.variable && r.offset == t.offset; }))
          reads.push_back(t);
      } else {
        TermRef t = term(n);
        carry(t, decide_);
        in.op = ValueOp::Term;
        in.slot = t.slot;
        in.variable = t.variable;
        in.offset = t.offset;
        in.cell = t.cell;
      }
      code.push_back(in);
    };
    auto op = [&](const Node& n) {
      ValueInstr in;
      in.op = value_op(n.kind);
      code.push_back(in);
    };
    p_.max_value_stack += postfix(ast_, root, is_operand, operand, op);
    p_.codes.push_back(std::move(code));
    return static_cast<uint32_t>(p_.codes.size() - 1);
  }

  uint32_t compile_aggregate(NodeIndex i) {
    const Node& n = ast_.nodes[i];
    const uint32_t index = static_cast<uint32_t>(p_.aggregates.size());
    AggregateCode a;
    a.kind = n.aggregate;
    a.slot = static_cast<int16_t>(n.x.slot);
    a.offset = static_cast<int16_t>(n.x.offset);
    a.domain = n.domain;
    if (n.aggregate == AggregateKind::Argmin || n.aggregate == AggregateKind::Argmax) {
      // What it gives is each element's id: read (and carried in a table) as its variables are.
      p_.reads_id = true;
      TermRef id;
      id.variable = kIdVariable;
      a.neighbor_reads.push_back(id);
    }
    a.hops = static_cast<int16_t>(n.domain == Domain::Within ? n.value : 1);
    p_.aggregates.push_back(a);
    const uint32_t outer = aggregate_;
    aggregate_ = index;
    if (n.rhs != kNoNode) {  // a component's condition
      int depth = 0;
      std::vector<ExprOp> ops = compile_condition(n.rhs, index, depth);
      p_.aggregates[index].member_condition = std::move(ops);
      p_.aggregates[index].member_depth = depth;
    }
    if (n.lhs != kNoNode) {
      if (n.aggregate == AggregateKind::Count) {
        int depth = 0;
        std::vector<ExprOp> ops = compile_condition(n.lhs, index, depth);
        p_.aggregates[index].condition = std::move(ops);
        p_.aggregates[index].condition_depth = depth;
      } else {
        const uint32_t value = compile_value(n.lhs);
        p_.aggregates[index].value = value;
      }
    }
    aggregate_ = outer;
    if ((a.domain == Domain::Within || a.domain == Domain::Component) && a.slot != decide_) {
      // Read where it is decided from the engine's history of every module (what h rounds of
      // messages bring, docs/design.md §4c), around the module the PatternMatcher carries: no table.
      carries_ = true;
    } else if (a.domain == Domain::Neighbors && a.slot != decide_) {
      carries_ = true;
      p_.sets.push_back({a.slot, a.offset, static_cast<int32_t>(index)});
      p_.aggregates[index].table = static_cast<int16_t>(p_.sets.size() - 1);
    }
    return index;
  }

  // A condition as postfix logic over tests; `aggregate` is the one its bound name belongs to
  // (meaningful inside one only). `depth` is the truths its evaluation needs.
  std::vector<ExprOp> compile_condition(NodeIndex root, uint32_t aggregate, int& depth) {
    std::vector<ExprOp> ops;
    auto test = [&](NodeIndex i) {
      const Node& n = ast_.nodes[i];
      ConditionTest t;
      if (n.kind == NodeKind::Compare) {
        t.kind = ConditionTest::Kind::Compare;
        t.op = n.op;
        t.lhs = compile_value(n.lhs);
        t.rhs = compile_value(n.rhs);
      } else {
        t.kind = ConditionTest::Kind::Neighbor;
        t.x = n.x.bound ? kBound : static_cast<int16_t>(n.x.slot);
        t.y = n.y.bound ? kBound : static_cast<int16_t>(n.y.slot);
        t.offset = static_cast<int16_t>(n.x.offset);
        if (n.x.bound) {
          std::vector<int16_t>& sets = p_.aggregates[aggregate].neighbor_sets;
          if (std::find(sets.begin(), sets.end(), t.offset) == sets.end()) sets.push_back(t.offset);
        } else if (t.x != decide_) {
          t.set = carried_set(t.x, t.offset);
        }
        // `neighbor(n a)` reads which module fills slot a: for any other slot than the decide
        // slot's, the leaf is no own leaf (it is not the same for every binding of its module).
        if (t.y != kBound && t.y != decide_) carries_ = true;
      }
      p_.tests.push_back(t);
      ops.push_back({ExprOp::PushLeaf, static_cast<uint32_t>(p_.tests.size() - 1)});
    };
    auto op = [&](const Node& n) { ops.push_back({logic_op(n.kind), 0}); };
    depth = postfix(ast_, root, is_test, test, op);
    p_.max_condition_stack += depth;
    return ops;
  }

  const Ast& ast_;
  const Analysis& analysis_;
  Program& p_;
  int16_t decide_ = 0;                      // the decide slot of what is being compiled
  uint32_t aggregate_ = 0;                  // the aggregate whose body is being compiled
  std::map<NodeIndex, size_t> kept_index_;  // a kept window as written -> Program::kept_windows
  std::vector<int> kept_read_offset_;       // per kept window: the earliest offset it is read at
  bool carries_ = false;                    // the leaf being compiled reads a cell, a set or a table
};

}  // namespace

Program::Program(const Ast& ast, const Analysis& analysis) { Compiler(ast, analysis, *this).run(); }

}  // namespace dw::watch
