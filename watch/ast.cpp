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

const char* aggregate_name(AggregateKind k) {
  switch (k) {
    case AggregateKind::Count: return "count";
    case AggregateKind::Sum: return "sum";
    case AggregateKind::Min: return "min";
    case AggregateKind::Max: return "max";
    case AggregateKind::Argmin: return "argmin";
    case AggregateKind::Argmax: return "argmax";
  }
  return "?";
}

const char* window_name(WindowKind k) {
  switch (k) {
    case WindowKind::Once: return "once";
    case WindowKind::Historically: return "historically";
    case WindowKind::Times: return "times";
    case WindowKind::Since: return "since";
  }
  return "?";
}

std::string to_string(const Ast& ast, const ModuleRef& m, std::string_view bound) {
  std::string out = m.bound ? std::string(bound) : m.slot >= 0 ? ast.slots[m.slot].name : "?";
  for (int i = 0; i < m.offset; ++i) out += ".next";
  for (int i = 0; i > m.offset; --i) out += ".last";
  return out;
}

namespace {

// Binding strength of an arithmetic node: what decides whether a child needs parentheses.
int precedence(NodeKind k) {
  switch (k) {
    case NodeKind::Add:
    case NodeKind::Subtract: return 1;
    case NodeKind::Multiply:
    case NodeKind::Divide:
    case NodeKind::Remainder: return 2;
    case NodeKind::Negate: return 3;
    default: return 4;  // atoms
  }
}

const char* operator_spelling(NodeKind k) {
  switch (k) {
    case NodeKind::Add: return " + ";
    case NodeKind::Subtract: return " - ";
    case NodeKind::Multiply: return " * ";
    case NodeKind::Divide: return " / ";
    case NodeKind::Remainder: return " % ";
    default: return " ? ";
  }
}

class Printer {
 public:
  Printer(const Ast& ast, std::string& out) : ast_(ast), out_(out) {}

  void print(NodeIndex i) {
    const Node& n = ast_.nodes[i];
    switch (n.kind) {
      case NodeKind::Not: {
        out_ += "not ";
        const NodeKind k = ast_.nodes[n.lhs].kind;
        grouped(n.lhs, k == NodeKind::And || k == NodeKind::Or);
        return;
      }
      case NodeKind::And:
      case NodeKind::Or: {
        // A child of an and/or is grouped when it is the other one of the two, so that precedence
        // never has to be remembered by the reader.
        auto child = [&](NodeIndex c) {
          const NodeKind k = ast_.nodes[c].kind;
          grouped(c, (k == NodeKind::And || k == NodeKind::Or) && k != n.kind);
        };
        child(n.lhs);
        out_ += n.kind == NodeKind::And ? " and " : " or ";
        child(n.rhs);
        return;
      }
      case NodeKind::Neighbor:
        out_ += "neighbor(" + to_string(ast_, n.x, bound_) + ' ' + to_string(ast_, n.y, bound_) + ')';
        return;
      case NodeKind::Compare:
        out_ += '(';
        print(n.lhs);
        out_ += ' ';
        out_ += spelling(n.op);
        out_ += ' ';
        print(n.rhs);
        out_ += ')';
        return;
      case NodeKind::Error: out_ += "<error>"; return;
      case NodeKind::Integer: out_ += std::to_string(n.value); return;
      case NodeKind::Variable: out_ += to_string(ast_, n.x, bound_) + '.' + n.name; return;
      case NodeKind::Negate: {
        out_ += '-';
        // `-(x)` of a literal stays grouped, or it would read back as a negative literal. `- -x`
        // is not grouped: parentheses would double the nesting the parser allows (a chain of 200
        // minus signs would print past its limit and not read back).
        const Node& operand = ast_.nodes[n.lhs];
        // Of a literal 0 or below, `- -5` reads back as this same tree, with no group.
        if (operand.kind == NodeKind::Integer && operand.value == 0) {
          out_ += " -0";
          return;
        }
        if (operand.kind == NodeKind::Negate || (operand.kind == NodeKind::Integer && operand.value < 0)) {
          out_ += ' ';
          print(n.lhs);
          return;
        }
        grouped(n.lhs, precedence(operand.kind) < 3 || operand.kind == NodeKind::Integer);
        return;
      }
      case NodeKind::Add:
      case NodeKind::Subtract:
      case NodeKind::Multiply:
      case NodeKind::Divide:
      case NodeKind::Remainder: {
        const int p = precedence(n.kind);
        // Left-associative: the left child is grouped when it binds less, the right when it binds
        // no more. A negative literal on the right is grouped too, so `a - (-1)` stays readable.
        grouped(n.lhs, precedence(ast_.nodes[n.lhs].kind) < p);
        out_ += operator_spelling(n.kind);
        const Node& r = ast_.nodes[n.rhs];
        grouped(n.rhs, precedence(r.kind) <= p || (r.kind == NodeKind::Integer && r.value < 0));
        return;
      }
      case NodeKind::Abs:
        out_ += "abs(";
        print(n.lhs);
        out_ += ')';
        return;
      case NodeKind::Min:
      case NodeKind::Max:
        out_ += n.kind == NodeKind::Min ? "min(" : "max(";
        print(n.lhs);
        out_ += ", ";
        print(n.rhs);
        out_ += ')';
        return;
      case NodeKind::Aggregate: {
        const std::string saved = bound_;
        bound_ = n.name;
        out_ += std::string(aggregate_name(n.aggregate)) + '(' + n.name + " in ";
        if (n.domain == Domain::All) out_ += "all";
        else if (n.domain == Domain::Within)
          out_ += "within(" + to_string(ast_, n.x) + ", " + std::to_string(n.value) + ')';
        else if (n.domain == Domain::Component) {
          out_ += "component(" + to_string(ast_, n.x) + ": ";
          print(n.rhs);
          out_ += ')';
        } else out_ += "neighbors(" + to_string(ast_, n.x) + ')';
        if (n.lhs != kNoNode) {
          out_ += ": ";
          print(n.lhs);
        }
        out_ += ')';
        bound_ = saved;
        return;
      }
      case NodeKind::Window:
      case NodeKind::Id:
      case NodeKind::Step:
      case NodeKind::Truth:
      case NodeKind::KeptWindow: print_window_term(n); return;
    }
  }

  // docs/design.md §4c: windows and id(), and what watch/windows.h writes them out with.
  void print_window_term(const Node& n) {
    switch (n.kind) {
      case NodeKind::Window:
        out_ += window_name(n.window);
        if (n.value > 0) out_ += '[' + std::to_string(n.value) + ']';
        out_ += '(';
        print(n.lhs);
        if (n.rhs != kNoNode) {
          out_ += ", ";
          print(n.rhs);
        }
        out_ += ')';
        return;
      case NodeKind::Id:
        out_ += "id(" + to_string(ast_, n.x, bound_) + ')';
        return;
        // Never printed as the watchpoint (they are in the evaluated tree only); spelled for a reader.
      case NodeKind::Step: out_ += "step(" + to_string(ast_, n.x, bound_) + ')'; return;
      case NodeKind::Truth:
        out_ += "truth(";
        print(n.lhs);
        out_ += ')';
        return;
      case NodeKind::KeptWindow: {
        const int64_t k = ast_.nodes[static_cast<size_t>(n.value)].value;
        out_ += window_name(n.window);
        if (k > 0) out_ += '[' + std::to_string(k) + ']';
        out_ += '(';
        print(n.lhs);
        if (n.rhs != kNoNode) {
          out_ += ", ";
          print(n.rhs);
        }
        out_ += ")@" + to_string(ast_, n.x, bound_);
        return;
      }
      default: return;
    }
  }

 private:
  void grouped(NodeIndex c, bool group) {
    if (group) out_ += '(';
    print(c);
    if (group) out_ += ')';
  }

  const Ast& ast_;
  std::string& out_;
  std::string bound_ = "n";
};

}  // namespace

std::string to_string(const Ast& ast, NodeIndex node) {
  std::string out;
  Printer(ast, out).print(node);
  return out;
}

std::string to_string(const Ast& ast) {
  std::string out = "modules(";
  for (size_t i = 0; i < ast.slots.size(); ++i) out += (i ? " " : "") + ast.slots[i].name;
  out += "); ";
  Printer printer(ast, out);
  if (ast.root != kNoNode) printer.print(ast.root);
  for (size_t i = 0; i < ast.actions.size(); ++i) {
    const Action& a = ast.actions[i];
    out += i == 0 ? " then " : ", ";
    const std::string slot = a.slot >= 0 ? ast.slots[a.slot].name : "?";
    if (a.kind == Action::Kind::Remove) {
      out += "remove " + slot;
      continue;
    }
    out += "set " + slot + '.' + a.variable + " = ";
    printer.print(a.value);
  }
  return out;
}

Span first_use(const Ast& ast, std::string_view variable) {
  Span first{};
  for (const Node& n : ast.nodes)
    if (n.kind == NodeKind::Variable && n.name == variable && (first.length() == 0 || n.span.begin < first.begin))
      first = n.span;
  return first;
}

Span first_set(const Ast& ast, std::string_view variable) {
  for (const Action& a : ast.actions)
    if (a.kind == Action::Kind::Set && a.variable == variable) return a.variable_span;
  return {};
}

}  // namespace dw::watch
