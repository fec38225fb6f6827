#include "watch/parser.h"

#include <cstdlib>
#include <string>

#include "watch/parser_impl.h"

namespace dw::watch {
namespace detail {

bool starts_expression(TokenKind k) {
  return k == TokenKind::Name || k == TokenKind::Integer || k == TokenKind::NonInteger || k == TokenKind::Minus ||
         k == TokenKind::LParen || k == TokenKind::Abs || k == TokenKind::Min || k == TokenKind::Max ||
         k == TokenKind::Count || k == TokenKind::Sum || k == TokenKind::Times || k == TokenKind::Id ||
         k == TokenKind::Argmin || k == TokenKind::Argmax;
}

bool starts_window_condition(TokenKind k) {
  return k == TokenKind::Once || k == TokenKind::Historically || k == TokenKind::Since;
}

// ---- grammar: the watchpoint --------------------------------------------------------------

// watchpoint := 'modules' '(' (NAME (','? NAME)*)? ')' ';' or ['then' action (',' action)*] END
// (no module: a zero-slot watchpoint on the whole ensemble, docs/design.md §4c)
void Parser::parse_watchpoint() {
  // After a broken module list every name below would be "undeclared": one mistake, one message.
  if (!parse_module_decl()) return;
  if (!match(TokenKind::Semicolon)) {
    error_expected("';' after the module list");
    // Going on is only useful when the condition clearly starts here.
    if (!check(TokenKind::Not) && !check(TokenKind::Neighbor) && !starts_expression(peek().kind) &&
        !starts_window_condition(peek().kind))
      return;
    panic_ = false;
  }
  if (check(TokenKind::End)) {
    const uint32_t after = previous().span.end;
    error_at({after, after}, "expected a condition after ';'");
    return;
  }
  ast_.root = parse_or(0);
  if (bail_) return;
  if (check(TokenKind::Then)) parse_actions();
  if (bail_) return;
  if (!check(TokenKind::End)) {
    if (check(TokenKind::RParen)) error_at(peek().span, "unmatched ')'");
    else error_expected(ast_.actions.empty() ? "'and', 'or' or end of input" : "',' or end of input");
  }
}

// module-decl := 'modules' '(' (NAME (','? NAME)*)? ')'
// Whether the list was read whole (possibly empty) with no keyword in it.
bool Parser::parse_module_decl() {
  if (!check(TokenKind::Modules)) {
    error_expected("'modules(...)' at the start of a watchpoint");
    // Recover only if the declaration is just misspelled: NAME '(' ...
    if (!(check(TokenKind::Name) && at(pos_ + 1).kind == TokenKind::LParen)) return false;
    panic_ = false;
  }
  advance();
  if (!expect(TokenKind::LParen, "'(' after 'modules'")) return false;
  bool keyword_named = false;  // a keyword in the list is the mistake; the list is not also empty
  while (!check(TokenKind::RParen)) {
    if (!ast_.slots.empty()) match(TokenKind::Comma);
    if (check(TokenKind::Name)) {
      const Token& t = advance();
      const std::string name(source_.slice(t.span));
      bool duplicate = false;
      for (const SlotDecl& s : ast_.slots) duplicate |= s.name == name;
      if (duplicate) report(t.span, "module '" + name + "' is declared twice");
      else if (ast_.slots.size() < kMaxSlots) ast_.slots.push_back({name, t.span});
      else if (!too_many_slots_) {
        report(t.span, "too many modules: a watchpoint may declare at most " + std::to_string(kMaxSlots));
        too_many_slots_ = true;
      }
    } else if (is_keyword(peek().kind)) {
      error_at(peek().span, "keyword " + describe(peek().kind) + " cannot be a module name");
      advance();
      panic_ = false;
      keyword_named = true;
    } else {
      error_expected(ast_.slots.empty() ? "a module name" : "a module name or ')'");
      while (!check(TokenKind::End) && !check(TokenKind::RParen) && !check(TokenKind::Semicolon)) advance();
      match(TokenKind::RParen);
      panic_ = false;
      return false;
    }
  }
  advance();  // ')'
  return !(keyword_named && ast_.slots.empty());
}

// actions := 'then' action (',' action)*
// action  := 'set' NAME '.' NAME '=' expr | 'remove' NAME
void Parser::parse_actions() {
  advance();                 // 'then'
  if (ast_.slots.empty()) {  // docs/design.md §4c: a zero-slot watchpoint has no module to act on
    error_at(previous().span, "a watchpoint with no modules ('modules()') has no module to act on: 'then' is refused");
    return;
  }
  do {
    if (bail_) return;
    const Span start = peek().span;
    Action a;
    if (match(TokenKind::Remove)) {
      a.kind = Action::Kind::Remove;
      ModuleRef m;
      if (!parse_action_slot(m, "remove")) return;
      a.slot = m.slot;
    } else if (match(TokenKind::Set)) {
      ModuleRef m;
      if (!parse_action_slot(m, "set")) return;
      a.slot = m.slot;
      if (!expect(TokenKind::Dot, "'.' and the variable to set after '" + std::string(source_.slice(m.span)) + "'"))
        return;
      if (check(TokenKind::Last) || check(TokenKind::Next)) {
        error_at(peek().span, "an action sets a variable at the step it acts: 'last' and 'next' do not apply");
        return;
      }
      if (!parse_variable_name(a.variable)) return;
      a.variable_span = previous().span;
      if (!expect(TokenKind::Equal,
                  "'=' after 'set " + std::string(source_.slice(Span::cover(m.span, previous().span))) + "'"))
        return;
      a.value = parse_expr(1);
      if (panic_) return;
    } else {
      const std::string what =
          std::string("an action ('set' or 'remove') after ") + (ast_.actions.empty() ? "'then'" : "','");
      if (check(TokenKind::End)) error_at({previous().span.end, previous().span.end}, "expected " + what);
      else error_expected(what);
      return;
    }
    a.span = Span::cover(start, previous().span);
    ast_.actions.push_back(std::move(a));
  } while (match(TokenKind::Comma));
}

// The slot an action names: a declared slot, never a bound name.
bool Parser::parse_action_slot(ModuleRef& out, const char* verb) {
  if (!check(TokenKind::Name)) {
    if (is_keyword(peek().kind)) error_at(peek().span, "keyword " + describe(peek().kind) + " cannot be a module name");
    else error_expected(std::string("the module to ") + verb);
    return false;
  }
  return parse_slot_name(out);
}

// ---- grammar: conditions ------------------------------------------------------------------

// or := and ('or' and)*
NodeIndex Parser::parse_or(int depth) {
  NodeIndex left = parse_and(depth);
  while (!bail_ && match(TokenKind::Or)) left = binary(NodeKind::Or, left, parse_and(depth));
  return left;
}

// and := not ('and' not)*
NodeIndex Parser::parse_and(int depth) {
  NodeIndex left = parse_not(depth);
  while (!bail_ && match(TokenKind::And)) left = binary(NodeKind::And, left, parse_not(depth));
  return left;
}

NodeIndex Parser::binary(NodeKind kind, NodeIndex l, NodeIndex r) {
  return node(kind, Span::cover(ast_.nodes[l].span, ast_.nodes[r].span), l, r);
}

// not := 'not' not | primary
NodeIndex Parser::parse_not(int depth) {
  if (!enter(depth)) return error_node(peek().span);
  if (check(TokenKind::Not)) {
    const Span kw = advance().span;
    const NodeIndex operand = parse_not(depth + 1);
    return node(NodeKind::Not, Span::cover(kw, ast_.nodes[operand].span), operand);
  }
  return parse_primary(depth);
}

// primary := 'neighbor' '(' module ','? module ')' | '(' or ')' | compare
//          | ('once' | 'historically') '[' INT ']' '(' or ')' | 'since' ['[' INT ']'] '(' or ',' or ')'
// The paper's `'(' compare ')'` is the case of `'(' or ')'` whose inside is one comparison; a
// bare comparison where a primary is expected is an accepted extension. A '(' that does not open
// a condition opens the first operand of a comparison (docs/design.md §4b).
NodeIndex Parser::parse_primary(int depth) {
  const Span start = peek().span;
  if (match(TokenKind::Neighbor)) return parse_neighbor(start);
  if (starts_window_condition(peek().kind)) return parse_window(depth);
  if (check(TokenKind::LParen) && opens_condition(depth)) {
    advance();
    const size_t diagnostics = diagnostics_.size();
    const NodeIndex inner = parse_or(depth + 1);
    if (bail_) return inner;
    if (!match(TokenKind::RParen)) {
      if (!panic_) {
        if (check(TokenKind::End)) error_at(start, "'(' is never closed");
        else error_expected("')'");
      }
      synchronize();
      match(TokenKind::RParen);
    }
    ast_.nodes[inner].span = Span::cover(start, previous().span);
    // A mistake inside may have been what made this a condition: what follows the group as an
    // operand would then only cascade from it.
    if (diagnostics_.size() > diagnostics && !check(TokenKind::And) && !check(TokenKind::Or) &&
        !check(TokenKind::RParen) && !check(TokenKind::Then) && !check(TokenKind::End)) {
      panic_ = true;
      synchronize();
    }
    return inner;
  }
  if (starts_expression(peek().kind)) return parse_compare(depth);
  error_expected("a condition ('(', 'not', 'neighbor', a window or a comparison)");
  synchronize();
  return error_node(start);
}

// Whether the '(' here opens a condition: it does when its contents parse as one (an `or` up to
// the matching ')'), and opens an integer expression otherwise. When neither parses, the reading
// that got further decides, so that its error is the one reported. Both readings are tried
// without a trace and the verdict kept by the '(' token, so that nested parentheses are
// decided once each (the work stays quadratic in the nesting, never exponential).
bool Parser::opens_condition(int depth) {
  if (auto known = verdicts_.find(pos_); known != verdicts_.end()) return known->second;
  auto attempt = [&](auto&& parse_inside) {
    const Saved saved = save();
    ++marks_;
    advance();
    parse_inside();
    const bool ok = syntax_error_at_ == kNone && !bail_ && check(TokenKind::RParen);
    const uint32_t reached = syntax_error_at_ != kNone ? syntax_error_at_ : peek().span.begin;
    --marks_;
    restore(saved);
    return std::pair(ok, reached);
  };
  const auto [condition, condition_reached] = attempt([&] { parse_or(depth + 1); });
  bool verdict = condition;
  if (!condition) {
    const auto [expression, expression_reached] = attempt([&] { parse_expr(depth + 1); });
    verdict = !expression && condition_reached >= expression_reached;
  }
  verdicts_[pos_] = verdict;
  return verdict;
}

// neighbor := 'neighbor' '(' module ','? module ')'
NodeIndex Parser::parse_neighbor(Span keyword) {
  Node n;
  n.kind = NodeKind::Neighbor;
  bool ok = expect(TokenKind::LParen, "'(' after 'neighbor'");
  if (ok) ok = parse_module_in_neighbor(n.x);
  if (ok) {
    match(TokenKind::Comma);
    ok = parse_module_in_neighbor(n.y);
  }
  if (ok) ok = expect(TokenKind::RParen, "')' after the two modules of neighbor()");
  if (!ok) {
    synchronize();
    match(TokenKind::RParen);
    return error_node(keyword);
  }
  n.span = Span::cover(keyword, previous().span);
  const bool x_known = n.x.slot >= 0 || n.x.bound, y_known = n.y.slot >= 0 || n.y.bound;
  if (x_known && y_known) {
    if (n.x.slot == n.y.slot && n.x.bound == n.y.bound) {
      report(n.span, "neighbor() needs two different modules; '" + name_of(n.x) + "' is never its own neighbour");
    } else if (n.x.offset != n.y.offset) {
      report(n.span, "neighbor() compares two modules at the same step, but '" + module_text(n.x) + "' is at offset " +
                         std::to_string(n.x.offset) + " and '" + module_text(n.y) + "' at offset " +
                         std::to_string(n.y.offset));
    }
  }
  return add(std::move(n));
}

// compare := expr OP expr
NodeIndex Parser::parse_compare(int depth) {
  const Span start = peek().span;
  const NodeIndex left = parse_expr(depth);
  if (panic_) {
    synchronize();
    return error_node(start);
  }
  if (!is_comparison(peek().kind)) {
    error_expected("a comparison operator (<, >, =, !=, >=, <=) after '" +
                   std::string(source_.slice(ast_.nodes[left].span)) + "'");
    synchronize();
    return error_node(start);
  }
  const CompareOp op = static_cast<CompareOp>(static_cast<int>(advance().kind) - static_cast<int>(TokenKind::Less));
  const NodeIndex right = parse_operand(depth, std::string("after '") + spelling(op) + "'");
  if (panic_) {
    synchronize();
    return error_node(start);
  }
  const NodeIndex n = binary(NodeKind::Compare, left, right);
  ast_.nodes[n].op = op;
  return n;
}

}  // namespace detail

ParseResult parse(const SourceText& source) { return detail::Parser(source).run(); }

}  // namespace dw::watch
