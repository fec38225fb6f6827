// The syntax tree of one watchpoint (paper Fig. 1, docs/design.md §3 and §4b). Nodes live in one vector and
// refer to each other by index, so a tree of any shape is freed without recursion. Children are
// always stored before their parents.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "watch/source.h"

namespace dw::watch {

using NodeIndex = int32_t;

// Most slots a watchpoint may declare. The number of PatternMatchers grows exponentially with it
// (paper §V-C); 32 is far past anything that finishes.
constexpr int kMaxSlots = 32;
constexpr NodeIndex kNoNode = -1;

// A slot named in `modules(...)`; slots are numbered in declaration order from 0.
struct SlotDecl {
  std::string name;
  Span span;
};

// `a.last.next`: slot `a` seen at a temporal offset (+1 per `next`, -1 per `last`), or, inside an
// aggregate, its bound name `n` (an offset from the aggregate's step).
struct ModuleRef {
  int32_t slot = -1;   // -1 when the name was not declared (already diagnosed) or is the bound name
  bool bound = false;  // the enclosing aggregate's bound name
  int32_t offset = 0;
  Span span;
};

enum class CompareOp : uint8_t { Less, Greater, Equal, NotEqual, GreaterEqual, LessEqual };
const char* spelling(CompareOp op);

enum class NodeKind : uint8_t {
  // conditions
  Not,
  And,
  Or,
  Neighbor,
  Compare,
  Error,
  // integer expressions (docs/design.md §4b)
  Integer,
  Variable,
  Negate,
  Add,
  Subtract,
  Multiply,
  Divide,
  Remainder,
  Abs,
  Min,  // of two
  Max,  // of two
  Aggregate,
  // docs/design.md §4c: a window in time (a condition, or `times`, an integer expression) and `id(m)`
  Window,
  Id,
  // Made by watch/windows.h when it writes a window out over its shifts, never by the parser:
  // `Step` is the step at which slot x's "now" plus x.offset falls (known before step 0 too),
  // `Truth` the integer 1, 0 or unknown of the condition lhs.
  Step,
  Truth,
  // A window kept by its module (watch/kept_windows.h), read at x: `value` is the window as written,
  // `window` its kind; lhs and rhs its φ and ψ as its module reads them (what the analysis keeps).
  KeptWindow,
};

// `once[k](φ)`, `historically[k](φ)`, `times[k](φ)`, `since[k](φ, ψ)`; k = 0 for an unbounded since.
enum class WindowKind : uint8_t { Once, Historically, Times, Since };
const char* window_name(WindowKind k);

// Argmin, Argmax (docs/design.md §4c): the id of the element of least / greatest value, ties to the least id.
enum class AggregateKind : uint8_t { Count, Sum, Min, Max, Argmin, Argmax };
const char* aggregate_name(AggregateKind k);

// What an aggregate ranges over (docs/design.md §4c): `neighbors(m)`, `within(m, h)` (1..h hops from
// m, m excluded; h in Node::value), `all` (every module present at the match's step: its x is
// slot 0 at the offset of the windows around it, the match step being slot 0's "now"),
// `component(m: c)` (the connected cluster around m where c holds; c is the node's rhs).
enum class Domain : uint8_t { Neighbors, Within, All, Component };

struct Node {
  NodeKind kind = NodeKind::Error;
  Span span;
  // Not, Negate, Abs: the operand (lhs). And, Or, Compare, the arithmetic operators, Min, Max:
  // left and right. Aggregate: its condition (Count, or kNoNode) or its value (the others), and
  // rhs a component's condition.
  // Window: its condition (since: φ, and rhs ψ). Truth: the condition.
  NodeIndex lhs = kNoNode;
  NodeIndex rhs = kNoNode;
  ModuleRef x, y;                   // Neighbor(x y); Variable, Id, Step: x; Aggregate: x, the module it ranges over
  CompareOp op = CompareOp::Equal;  // Compare
  int64_t value = 0;                // Integer; Window: its k (0: an unbounded since); within's h
  WindowKind window = WindowKind::Once;
  AggregateKind aggregate = AggregateKind::Count;
  Domain domain = Domain::Neighbors;  // Aggregate; Within's h is `value`
  std::string name;                   // Variable: the variable; Aggregate: the bound name
};

// `then set a.v = expr` or `then remove a` (docs/design.md §4b).
struct Action {
  enum class Kind : uint8_t { Set, Remove };
  Kind kind = Kind::Set;
  int32_t slot = -1;
  std::string variable;           // Set
  Span variable_span;             // Set: where `variable` is named
  NodeIndex value = kNoNode;      // Set: an integer expression
  NodeIndex evaluated = kNoNode;  // Set: `value` with its windows written out (watch/windows.h)
  Span span;
};

struct Ast {
  std::vector<SlotDecl> slots;
  std::vector<Node> nodes;
  NodeIndex root = kNoNode;  // as written: what is printed
  std::vector<Action> actions;
  // `root` with every window written out over its shifts (watch/windows.h): what is analysed and
  // compiled. Its nodes follow the written ones, which keep their indices.
  NodeIndex evaluated = kNoNode;
};

// What is analysed and compiled: the tree with its windows written out, or the one written.
inline NodeIndex evaluated_root(const Ast& ast) { return ast.evaluated != kNoNode ? ast.evaluated : ast.root; }
inline NodeIndex evaluated_value(const Action& a) { return a.evaluated != kNoNode ? a.evaluated : a.value; }

// The watchpoint in normal form: every comparison in parentheses, and/or chains flattened, mixed
// and/or grouped explicitly, arithmetic grouped only where precedence needs it. Printing is
// idempotent: parsing the result and printing it again gives the same text.
std::string to_string(const Ast& ast);
std::string to_string(const Ast& ast, const ModuleRef& m, std::string_view bound = "n");
// One node (a condition or an expression) in normal form.
std::string to_string(const Ast& ast, NodeIndex node);

// Calls visit(node, aggregate) for `root` and every node under it, parents before children, with
// the aggregate the node lies in (kNoNode outside any). Iterative: trees may be thousands deep.
template <class Visit>
void visit_tree(const Ast& ast, NodeIndex root, Visit&& visit) {
  struct Item {
    NodeIndex node, aggregate;
  };
  std::vector<Item> work{{root, kNoNode}};
  while (!work.empty()) {
    const Item it = work.back();
    work.pop_back();
    visit(it.node, it.aggregate);
    const Node& n = ast.nodes[static_cast<size_t>(it.node)];
    const NodeIndex inner = n.kind == NodeKind::Aggregate ? it.node : it.aggregate;
    if (n.rhs != kNoNode) work.push_back({n.rhs, inner});
    if (n.lhs != kNoNode) work.push_back({n.lhs, inner});
  }
}

// Where `variable` is first read (`a.last.x`), in source order; an empty span when it is not.
Span first_use(const Ast& ast, std::string_view variable);

// Where the first action that sets `variable` names it; empty if none does.
Span first_set(const Ast& ast, std::string_view variable);

}  // namespace dw::watch
