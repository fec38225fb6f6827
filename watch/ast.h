// The syntax tree of one watchpoint (paper Fig. 1, DESIGN §3). Nodes live in one vector and refer
// to each other by index, so a tree of any shape is freed without recursion.
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

// `a.last.next`: slot `a` seen at a temporal offset (+1 per `next`, -1 per `last`).
struct ModuleRef {
  int32_t slot = -1;  // -1 when the name was not declared (already diagnosed)
  int32_t offset = 0;
  Span span;
};

enum class CompareOp : uint8_t { Less, Greater, Equal, NotEqual, GreaterEqual, LessEqual };
const char* spelling(CompareOp op);

// One side of a comparison: a state variable `module.name`, or (right-hand side only) a constant.
struct Operand {
  bool is_constant = false;
  ModuleRef module;      // state variable
  std::string variable;  // state variable
  int64_t constant = 0;
  Span span;
};

enum class NodeKind : uint8_t { Not, And, Or, Neighbor, Compare, Error };

struct Node {
  NodeKind kind = NodeKind::Error;
  Span span;
  NodeIndex lhs = kNoNode;  // Not: operand; And/Or: left
  NodeIndex rhs = kNoNode;  // And/Or: right
  ModuleRef x, y;           // Neighbor(x y)
  CompareOp op = CompareOp::Equal;
  Operand left, right;  // Compare
};

struct Ast {
  std::vector<SlotDecl> slots;
  std::vector<Node> nodes;
  NodeIndex root = kNoNode;
};

// The watchpoint in normal form: every comparison in parentheses, and/or chains flattened, mixed
// and/or grouped explicitly. Printing is idempotent: parsing the result and printing it again
// gives the same text.
std::string to_string(const Ast& ast);
std::string to_string(const Ast& ast, const ModuleRef& m);
std::string to_string(const Ast& ast, const Operand& o);

// Where `variable` is first read (`a.last.x`), in source order; an empty span when it is not.
Span first_use(const Ast& ast, std::string_view variable);

}  // namespace dw::watch
