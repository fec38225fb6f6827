#include "watch/windows.h"

#include <algorithm>
#include <map>
#include <string>

namespace dw::watch {
namespace {

// How far the copy being made is lowered: every slot's offset by `slot` (the windows around it),
// and, inside an aggregate, its bound name's offsets by `bound` (the windows around it inside the
// aggregate only: the aggregate's own step is already lowered by the others).
struct Shift {
  int slot = 0, bound = 0;
  int aggregate_slot = -1, aggregate_offset = 0;  // the enclosing aggregate's module, as copied
  bool none() const { return slot == 0 && bound == 0; }
};

// What a window's condition reads at its shift 0 (docs/design.md §4c): the earliest offset per slot,
// and the earliest offset of the enclosing aggregate's bound name.
struct Reads {
  std::map<int, int> slot;  // slot -> earliest offset
  int latest = 0;           // the largest offset read, at least 0
  bool bound = false;
  int bound_offset = 0;
  void add_slot(int s, int offset) {
    auto [it, fresh] = slot.emplace(s, offset);
    if (!fresh) it->second = std::min(it->second, offset);
    latest = std::max(latest, offset);
  }
  void add_bound(int offset) {
    bound_offset = bound ? std::min(bound_offset, offset) : offset;
    bound = true;
  }
};

// What `root` (a window's condition, as written) reads at its shift 0: nested windows count as
// reading their own condition at their shift 0; an aggregate reads its module and, at its step
// plus their offsets, its bound name's variables and neighbour sets.
Reads reads_at_shift_zero(const Ast& ast, NodeIndex root) {
  Reads r;
  struct Item {
    NodeIndex node;
    int aggregate_slot, aggregate_offset;  // the aggregate inside `root` the node lies in, or -1
  };
  std::vector<Item> work{{root, -1, 0}};
  while (!work.empty()) {
    const Item it = work.back();
    work.pop_back();
    const Node& n = ast.nodes[static_cast<size_t>(it.node)];
    auto read = [&](const ModuleRef& m) {
      if (!m.bound) r.add_slot(m.slot, m.offset);
      else if (it.aggregate_slot >= 0) r.add_slot(it.aggregate_slot, it.aggregate_offset + m.offset);
      else r.add_bound(m.offset);  // the aggregate around the window
    };
    Item inner = it;
    switch (n.kind) {
      case NodeKind::Variable:
      case NodeKind::Id:
      case NodeKind::Neighbor: read(n.x); break;
      case NodeKind::Aggregate:
        read(n.x);
        inner = {it.node, n.x.slot, n.x.offset};
        break;
      default: break;
    }
    if (n.lhs != kNoNode) work.push_back({n.lhs, inner.aggregate_slot, inner.aggregate_offset});
    if (n.rhs != kNoNode) work.push_back({n.rhs, inner.aggregate_slot, inner.aggregate_offset});
  }
  return r;
}

class Writer {
 public:
  Writer(Ast& ast, WindowKeeping keeping)
      : ast_(ast), keeping_(keeping), written_(ast.nodes.size()), has_window_(ast.nodes.size(), 0) {
    // Children come before parents: one pass marks every node with a window under it.
    for (size_t i = 0; i < written_; ++i) {
      const Node& n = ast.nodes[i];
      has_window_[i] = n.kind == NodeKind::Window || (n.lhs != kNoNode && has_window_[n.lhs]) ||
                       (n.rhs != kNoNode && has_window_[n.rhs]);
    }
  }

  bool any() const { return std::find(has_window_.begin(), has_window_.end(), 1) != has_window_.end(); }

  NodeIndex copy(NodeIndex i, const Shift& s) {
    if (too_large_) return i;
    if (s.none() && !has_window_[static_cast<size_t>(i)]) return i;  // shared as written
    Node n = ast_.nodes[static_cast<size_t>(i)];
    if (n.kind == NodeKind::Window && keeping_ == WindowKeeping::ByModule && kept_by_module(ast_, i))
      return kept(i, n, s);
    if (n.kind == NodeKind::Window) return write_out(n, s);
    lower(n.x, s);
    if (n.kind == NodeKind::Neighbor) lower(n.y, s);
    Shift inner = s;
    if (n.kind == NodeKind::Aggregate) {
      inner.bound = 0;
      inner.aggregate_slot = n.x.slot;
      inner.aggregate_offset = n.x.offset;
    }
    if (n.lhs != kNoNode) n.lhs = copy(n.lhs, inner);
    if (n.rhs != kNoNode) n.rhs = copy(n.rhs, inner);
    return add(std::move(n));
  }

  bool too_large() const { return too_large_; }
  Span too_large_at() const { return too_large_at_; }

 private:
  static void lower(ModuleRef& m, const Shift& s) {
    if (m.slot < 0 && !m.bound) return;
    m.offset -= m.bound ? s.bound : s.slot;
  }

  NodeIndex add(Node n) {
    if (ast_.nodes.size() - written_ >= kMaxEvaluatedNodes && !too_large_) {
      too_large_ = true;
      too_large_at_ = n.span;
    }
    ast_.nodes.push_back(std::move(n));
    return static_cast<NodeIndex>(ast_.nodes.size() - 1);
  }

  NodeIndex make(NodeKind kind, Span span, NodeIndex lhs = kNoNode, NodeIndex rhs = kNoNode) {
    Node n;
    n.kind = kind;
    n.span = span;
    n.lhs = lhs;
    n.rhs = rhs;
    return add(std::move(n));
  }
  NodeIndex integer(int64_t v, Span span) {
    Node n;
    n.kind = NodeKind::Integer;
    n.span = span;
    n.value = v;
    return add(std::move(n));
  }
  NodeIndex compare(NodeIndex l, CompareOp op, NodeIndex r, Span span) {
    const NodeIndex c = make(NodeKind::Compare, span, l, r);
    ast_.nodes[static_cast<size_t>(c)].op = op;
    return c;
  }
  NodeIndex step(int slot, int offset, Span span) {
    Node n;
    n.kind = NodeKind::Step;
    n.span = span;
    n.x.slot = slot;
    n.x.offset = offset;
    return add(std::move(n));
  }

  // What `root` (a window's condition, as written) reads at its shift 0: nested windows count as
  // reading their own condition at their shift 0; an aggregate reads its module and, at its step
  // plus their offsets, its bound name's variables and neighbour sets.
  Reads reads_of(NodeIndex root) const { return reads_at_shift_zero(ast_, root); }

  // The step of the earliest read of the window's condition at shift 0, lowered by `s`: j is kept
  // exactly when this is at least j. A condition that reads nothing reads the match step (slot
  // 0's "now"), lowered by the windows around it.
  NodeIndex earliest(const Reads& r, const Shift& s, Span span) {
    NodeIndex m = kNoNode;
    auto fold = [&](NodeIndex st) { m = m == kNoNode ? st : make(NodeKind::Min, span, m, st); };
    for (const auto& [slot, offset] : r.slot) fold(step(slot, offset - s.slot, span));
    if (r.bound) fold(step(s.aggregate_slot, s.aggregate_offset + r.bound_offset - s.bound, span));
    if (m == kNoNode) fold(step(0, -s.slot, span));
    return m;
  }

  // A window kept by its module (watch/kept_windows.h): its column, read at the slot's "now" lowered
  // by the windows around it, and its conditions as written out once (what the columns are worked
  // out from, and what the analysis keeps the history for). A condition is its column = 1.
  NodeIndex kept(NodeIndex written, const Node& w, const Shift& s) {
    Reads r = reads_of(w.lhs);
    if (w.rhs != kNoNode)
      for (const auto& [slot, offset] : reads_of(w.rhs).slot) r.add_slot(slot, offset);
    // Conditions that read only ahead are kept lifted to read from their own step on, the column
    // read as far ahead: the same j are kept (watch/windows.h).
    const int lift = kept_steps(ast_, written).lift;
    auto [it, fresh] = kept_conditions_.emplace(written, std::pair<NodeIndex, NodeIndex>{kNoNode, kNoNode});
    if (fresh) {
      const Shift lifted{lift, 0};
      it->second = {copy(w.lhs, lifted), w.rhs == kNoNode ? kNoNode : copy(w.rhs, lifted)};
    }
    Node b;
    b.kind = NodeKind::KeptWindow;
    b.window = w.window;
    b.span = w.span;
    b.value = written;
    b.x.slot = r.slot.empty() ? 0 : r.slot.begin()->first;
    b.x.offset = lift - s.slot;
    b.lhs = it->second.first;
    b.rhs = it->second.second;
    const NodeIndex column = add(std::move(b));
    if (w.window == WindowKind::Times) return column;
    return compare(column, CompareOp::Equal, integer(1, w.span), w.span);
  }

  NodeIndex write_out(const Node& w, const Shift& s) {
    Reads r = reads_of(w.lhs);
    if (w.rhs != kNoNode) {
      const Reads more = reads_of(w.rhs);
      for (const auto& [slot, offset] : more.slot) r.add_slot(slot, offset);
      if (more.bound) r.add_bound(more.bound_offset);
    }
    const Span span = w.span;
    const NodeIndex first = earliest(r, s, span);
    auto kept = [&](int j) { return compare(first, CompareOp::GreaterEqual, integer(j, span), span); };
    auto at = [&](NodeIndex cond, int j) {
      Shift shifted = s;
      shifted.slot += j;
      shifted.bound += j;
      return copy(cond, shifted);
    };
    // 0 when j = 0 is kept, unknown when no j is: a window with nothing to read has no verdict.
    const NodeIndex none_kept = make(NodeKind::Divide, span, integer(0, span), make(NodeKind::Truth, span, kept(0)));
    const int k = static_cast<int>(w.value);
    switch (w.window) {
      case WindowKind::Once: {
        NodeIndex any = compare(none_kept, CompareOp::Equal, integer(1, span), span);
        for (int j = 0; j <= k && !too_large_; ++j)
          any = make(NodeKind::Or, span, any, make(NodeKind::And, span, kept(j), at(w.lhs, j)));
        return any;
      }
      case WindowKind::Historically: {
        NodeIndex all = compare(none_kept, CompareOp::Equal, integer(0, span), span);
        for (int j = 0; j <= k && !too_large_; ++j)
          all = make(NodeKind::And, span, all,
                     make(NodeKind::Or, span, make(NodeKind::Not, span, kept(j)), at(w.lhs, j)));
        return all;
      }
      case WindowKind::Times: {
        NodeIndex total = none_kept;
        for (int j = 0; j <= k && !too_large_; ++j)
          total = make(NodeKind::Add, span, total,
                       make(NodeKind::Truth, span, make(NodeKind::And, span, kept(j), at(w.lhs, j))));
        return total;
      }
      case WindowKind::Since: {
        // since = T_0 where T_k = kept(k) and ψ(−k), T_j = (kept(j) and ψ(−j)) or (φ(−j) and T_{j+1}):
        // the `or` over kept j of ψ(−j) and φ(0) .. φ(−(j−1)), in k + 1 copies of each.
        NodeIndex tail = make(NodeKind::And, span, kept(k), at(w.rhs, k));
        for (int j = k - 1; j >= 0 && !too_large_; --j)
          tail = make(NodeKind::Or, span, make(NodeKind::And, span, kept(j), at(w.rhs, j)),
                      make(NodeKind::And, span, at(w.lhs, j), tail));
        return make(NodeKind::Or, span, compare(none_kept, CompareOp::Equal, integer(1, span), span), tail);
      }
    }
    return kNoNode;
  }

  Ast& ast_;
  WindowKeeping keeping_;
  std::map<NodeIndex, std::pair<NodeIndex, NodeIndex>> kept_conditions_;  // by kept window: φ, ψ
  size_t written_;
  std::vector<uint8_t> has_window_;
  bool too_large_ = false;
  Span too_large_at_;
};

}  // namespace

int64_t window_reach(const Ast& ast, NodeIndex window) {
  struct Item {
    NodeIndex node;
    int64_t below;      // the steps the windows from `window` down to this node look back
    int aggregate_off;  // the enclosing aggregate's offset, for a bound name's reads
  };
  int64_t reach = 0;
  std::vector<Item> work{{window, 0, 0}};
  while (!work.empty()) {
    const Item it = work.back();
    work.pop_back();
    const Node& n = ast.nodes[static_cast<size_t>(it.node)];
    int64_t below = it.below;
    int aggregate_off = it.aggregate_off;
    auto read = [&](const ModuleRef& m) {
      const int offset = m.bound ? aggregate_off + m.offset : m.offset;
      reach = std::max(reach, below - offset);
    };
    switch (n.kind) {
      case NodeKind::Window: below += n.value; break;
      case NodeKind::Aggregate:
        read(n.x);
        aggregate_off = n.x.offset;
        break;
      case NodeKind::Variable:
      case NodeKind::Id:
      case NodeKind::Neighbor: read(n.x); break;
      default: break;
    }
    reach = std::max(reach, below);
    if (n.rhs != kNoNode) work.push_back({n.rhs, below, aggregate_off});
    if (n.lhs != kNoNode) work.push_back({n.lhs, below, aggregate_off});
  }
  return reach;
}

bool kept_by_module(const Ast& ast, NodeIndex window) {
  const Node& w = ast.nodes[static_cast<size_t>(window)];
  if (w.window == WindowKind::Since && w.value == 0) return true;  // the parser made sure
  int slot = -1;
  bool own = true;
  visit_tree(ast, window, [&](NodeIndex i, NodeIndex) {
    const Node& n = ast.nodes[static_cast<size_t>(i)];
    if (n.kind == NodeKind::Neighbor || n.kind == NodeKind::Aggregate || n.kind == NodeKind::Id) own = false;
    if (n.kind != NodeKind::Variable) return;
    if (n.x.bound || (slot >= 0 && n.x.slot != slot)) own = false;
    slot = n.x.slot;
  });
  return own && (slot >= 0 || !ast.slots.empty());
}

KeptSteps kept_steps(const Ast& ast, NodeIndex window) {
  const Node& w = ast.nodes[static_cast<size_t>(window)];
  Reads r = reads_at_shift_zero(ast, w.lhs);
  if (w.rhs != kNoNode) {
    const Reads more = reads_at_shift_zero(ast, w.rhs);
    for (const auto& [slot, offset] : more.slot) r.add_slot(slot, offset);
    r.latest = std::max(r.latest, more.latest);
  }
  KeptSteps k;
  if (r.slot.empty()) return k;                 // reads nothing: keeps j <= t
  const int earliest = r.slot.begin()->second;  // one slot
  k.lift = std::max(0, earliest);
  k.first_step = std::max(0, -earliest);
  k.ahead = r.latest - k.lift;
  return k;
}

std::vector<Diagnostic> write_out_windows(Ast& ast, WindowKeeping keeping) {
  Writer writer(ast, keeping);
  if (!writer.any()) return {};
  if (ast.root != kNoNode) ast.evaluated = writer.copy(ast.root, {});
  for (Action& a : ast.actions)
    if (a.kind == Action::Kind::Set) a.evaluated = writer.copy(a.value, {});
  if (writer.too_large())
    return {{writer.too_large_at(),
             "windows too long to evaluate: written out over their steps they would take more than " +
                 std::to_string(kMaxEvaluatedNodes) + " terms"}};
  return {};
}

}  // namespace dw::watch
