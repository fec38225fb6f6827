#include "watch/ast.h"

namespace dw::watch {

const char* spelling(CompareOp op) {
  switch (op) {
    case CompareOp::Less: return "<";
    case CompareOp::Greater: return ">";
    case CompareOp::Equal: return "=";
    case CompareOp::NotEqual: return "!=";
    case CompareOp::GreaterEqual: return ">=";
    case CompareOp::LessEqual: return "<=";
  }
  return "?";
}

std::string to_string(const Ast& ast, const ModuleRef& m) {
  std::string out = m.slot >= 0 ? ast.slots[m.slot].name : "?";
  for (int i = 0; i < m.offset; ++i) out += ".next";
  for (int i = 0; i > m.offset; --i) out += ".last";
  return out;
}

std::string to_string(const Ast& ast, const Operand& o) {
  if (o.is_constant) return std::to_string(o.constant);
  return to_string(ast, o.module) + "." + o.variable;
}

namespace {

void print(const Ast& ast, NodeIndex i, std::string& out) {
  const Node& n = ast.nodes[i];
  // A child of an and/or is grouped when it is the other one of the two, so that precedence never
  // has to be remembered by the reader.
  auto child = [&](NodeIndex c) {
    const NodeKind k = ast.nodes[c].kind;
    const bool group = (k == NodeKind::And || k == NodeKind::Or) && k != n.kind;
    if (group) out += '(';
    print(ast, c, out);
    if (group) out += ')';
  };
  switch (n.kind) {
    case NodeKind::Not: {
      out += "not ";
      const NodeKind k = ast.nodes[n.lhs].kind;
      const bool group = k == NodeKind::And || k == NodeKind::Or;
      if (group) out += '(';
      print(ast, n.lhs, out);
      if (group) out += ')';
      return;
    }
    case NodeKind::And:
    case NodeKind::Or:
      child(n.lhs);
      out += n.kind == NodeKind::And ? " and " : " or ";
      child(n.rhs);
      return;
    case NodeKind::Neighbor:
      out += "neighbor(";
      out += to_string(ast, n.x);
      out += ' ';
      out += to_string(ast, n.y);
      out += ')';
      return;
    case NodeKind::Compare:
      out += '(';
      out += to_string(ast, n.left);
      out += ' ';
      out += spelling(n.op);
      out += ' ';
      out += to_string(ast, n.right);
      out += ')';
      return;
    case NodeKind::Error: out += "<error>"; return;
  }
}

}  // namespace

std::string to_string(const Ast& ast) {
  std::string out = "modules(";
  for (size_t i = 0; i < ast.slots.size(); ++i) out += (i ? " " : "") + ast.slots[i].name;
  out += "); ";
  if (ast.root != kNoNode) print(ast, ast.root, out);
  return out;
}

Span first_use(const Ast& ast, std::string_view variable) {
  Span first{};
  for (const Node& n : ast.nodes) {
    if (n.kind != NodeKind::Compare) continue;
    for (const Operand* o : {&n.left, &n.right})
      if (!o->is_constant && o->variable == variable && (first.length() == 0 || o->span.begin < first.begin))
        first = o->span;
  }
  return first;
}

}  // namespace dw::watch
