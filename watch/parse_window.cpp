// The watchpoint grammar's windows in time and `id()` (docs/design.md §4c); the parser's state is
// watch/parser_impl.h, the conditions watch/parser.cpp, the integer expressions
// watch/parse_expression.cpp.
#include <algorithm>
#include <climits>
#include <string>
#include <vector>

#include "watch/parser_impl.h"
#include "watch/windows.h"

namespace dw::watch::detail {

namespace {

WindowKind window_kind(TokenKind k) {
  switch (k) {
    case TokenKind::Once: return WindowKind::Once;
    case TokenKind::Historically: return WindowKind::Historically;
    case TokenKind::Times: return WindowKind::Times;
    default: return WindowKind::Since;
  }
}

bool starts_operator(TokenKind k) {
  return k == TokenKind::Plus || k == TokenKind::Minus || k == TokenKind::Star || k == TokenKind::Slash ||
         k == TokenKind::Percent;
}

}  // namespace

// window := ('once' | 'historically' | 'times') '[' INT ']' '(' or ')'
//         | 'since' ['[' INT ']'] '(' or ',' or ')'
// `times` is an integer expression (an atom), the others conditions (primaries).
NodeIndex Parser::parse_window(int depth) {
  const Token& kw = advance();
  Node n;
  n.kind = NodeKind::Window;
  n.window = window_kind(kw.kind);
  const std::string what = window_name(n.window);
  const Span start = kw.span;
  // On a mistake before the window's '(', the caller recovers as after any bad primary or atom.
  auto fail = [&] {
    if (n.window != WindowKind::Times) synchronize();
    return error_node(start);
  };
  if (n.window != WindowKind::Since || check(TokenKind::LBracket)) {
    if (!parse_window_length(n, what)) return fail();
  }
  if (!expect(TokenKind::LParen, "'(' and the window's condition after '" +
                                     std::string(source_.slice(Span::cover(start, previous().span))) + "'"))
    return fail();
  const Span open = previous().span;
  // A mistake inside has been said once: what it left behind (a missing ',' or ')') is no second.
  const size_t said = diagnostics_.size();
  auto troubled = [&] { return panic_ || diagnostics_.size() > said; };
  n.lhs = parse_or(depth + 1);
  if (!bail_ && !troubled() && n.window == WindowKind::Since) {
    if (expect(TokenKind::Comma,
               "',' and the condition that starts it: since(φ, ψ) holds where ψ held and φ "
               "has held at every step after"))
      n.rhs = parse_or(depth + 1);
  }
  if (bail_) return error_node(start);
  if (n.window == WindowKind::Since && n.rhs == kNoNode) {  // φ went wrong, or no ',' after it
    if (match(TokenKind::RParen)) return error_node(start);
    return skip_group(start);
  }
  if (!match(TokenKind::RParen)) {
    if (!troubled()) {
      if (check(TokenKind::End)) error_at(open, "'(' is never closed");
      else error_expected("')' to close '" + what + "('");
    }
    // Up to the ')' that closes the window (the error stays in force for the caller to recover).
    return skip_group(start);
  }
  n.span = Span::cover(start, previous().span);
  const WindowKind kind = n.window;
  const bool unbounded = kind == WindowKind::Since && n.value == 0;
  const NodeIndex window = add(std::move(n));
  check_reach(window);
  if (unbounded) check_one_module(window);
  if (kind != WindowKind::Times && (is_comparison(peek().kind) || starts_operator(peek().kind))) {
    error_at(peek().span,
             "'" + what + "[...]' is a condition, not a number: count the steps it holds with 'times[k](...)'");
    synchronize();
  }
  return window;
}

// '[' INT ']': a window's length k, 1 to kMaxOffset steps.
bool Parser::parse_window_length(Node& n, const std::string& what) {
  if (!expect(TokenKind::LBracket, "'[' and the window's length after '" + what + "', as in '" + what + "[5](...)'"))
    return false;
  const Token& k = peek();
  if (k.kind == TokenKind::NonInteger) {
    error_at(k.span, "a window's length is a whole number of steps, not '" + std::string(source_.slice(k.span)) + "'");
    return false;
  }
  if (k.kind != TokenKind::Integer) {
    error_expected("the window's length in steps (1 to " + std::to_string(kMaxOffset) + ")");
    return false;
  }
  advance();
  if (k.overflow || k.value < 1 || k.value > static_cast<uint64_t>(kMaxOffset))
    report(k.span, "a window's length is 1 to " + std::to_string(kMaxOffset) + " steps");
  else n.value = static_cast<int64_t>(k.value);
  return expect(TokenKind::RBracket, "']' after the window's length");
}

// A window's reach (its k, plus the deepest 'last' inside it, nested windows added) counts toward
// the offset limit (docs/design.md §3): one error for the watchpoint, as for offsets.
void Parser::check_reach(NodeIndex window) {
  if (offset_reported_) return;
  const int64_t reach = window_reach(ast_, window);
  if (reach <= kMaxOffset) return;
  offset_reported_ = true;
  report(ast_.nodes[static_cast<size_t>(window)].span,
         "this window reaches " + std::to_string(reach) + " steps back (its length plus the deepest 'last' inside): " +
             "a watchpoint looks at most " + std::to_string(kMaxOffset) + " steps back or ahead");
}

// An unbounded since is kept by each module as one bit a step (docs/design.md §4c): its conditions
// read one slot's own variables only.
void Parser::check_one_module(NodeIndex since) {
  int slot = -1;
  int earliest = INT32_MAX;  // its earliest read (nested windows count their conditions at shift 0)
  std::string why;
  visit_tree(ast_, since, [&](NodeIndex i, NodeIndex) {
    const Node& n = ast_.nodes[static_cast<size_t>(i)];
    if (!why.empty()) return;
    if (n.kind == NodeKind::Neighbor) why = "neighbor()";
    else if (n.kind == NodeKind::Aggregate) why = "an aggregate";
    else if ((n.kind == NodeKind::Variable || n.kind == NodeKind::Id) && n.x.bound) why = "a bound name";
    else if (n.kind == NodeKind::Variable || n.kind == NodeKind::Id) {
      if (slot >= 0 && n.x.slot >= 0 && n.x.slot != slot) why = "a second module";
      if (n.x.slot >= 0) slot = n.x.slot;
      earliest = std::min(earliest, n.x.offset);
    }
  });
  // A since whose conditions only look ahead would start before step 0, where no bit is kept.
  if (why.empty() && earliest != INT32_MAX && earliest > 0) why = "only 'next' steps (read one at its step or before)";
  if (!why.empty())
    report(ast_.nodes[static_cast<size_t>(since)].span,
           "an unbounded since(...) reads one module's own variables, not " + why + ": give it a bound, since[k](...)");
}

// 'id' '(' module ')'
NodeIndex Parser::parse_id() {
  const Span start = advance().span;
  Node n;
  n.kind = NodeKind::Id;
  if (!expect(TokenKind::LParen, "'(' after 'id'")) return error_node(start);
  if (!parse_module_in_neighbor(n.x, "id()")) return skip_group(start);
  if (!expect(TokenKind::RParen, "')' after the module of id()")) return skip_group(start);
  n.span = Span::cover(start, previous().span);
  return add(std::move(n));
}

}  // namespace dw::watch::detail
