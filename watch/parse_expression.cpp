// The watchpoint grammar's integer expressions (docs/design.md §4b), modules and state variables; the
// parser's state is watch/parser_impl.h, the conditions watch/parser.cpp.
#include <cstdlib>
#include <string>

#include "watch/parser_impl.h"

namespace dw::watch::detail {

// expr := mul (('+' | '-') mul)*
NodeIndex Parser::parse_expr(int depth) {
  NodeIndex left = parse_mul(depth);
  while (!panic_ && !bail_ && (check(TokenKind::Plus) || check(TokenKind::Minus))) {
    const TokenKind op = advance().kind;
    const NodeIndex right = parse_operand(depth, "after " + describe(op), &Parser::parse_mul);
    left = binary(op == TokenKind::Plus ? NodeKind::Add : NodeKind::Subtract, left, right);
  }
  return left;
}

// mul := unary (('*' | '/' | '%') unary)*
NodeIndex Parser::parse_mul(int depth) {
  NodeIndex left = parse_unary(depth);
  while (!panic_ && !bail_ && (check(TokenKind::Star) || check(TokenKind::Slash) || check(TokenKind::Percent))) {
    const TokenKind op = advance().kind;
    const NodeIndex right = parse_operand(depth, "after " + describe(op), &Parser::parse_unary);
    left = binary(op == TokenKind::Star    ? NodeKind::Multiply
                  : op == TokenKind::Slash ? NodeKind::Divide
                                           : NodeKind::Remainder,
                  left, right);
  }
  return left;
}

// unary := '-' unary | atom        -- '-' INT folds into one constant: -9223372036854775808
NodeIndex Parser::parse_unary(int depth) {
  if (!enter(depth)) return error_node(peek().span);
  if (!check(TokenKind::Minus)) return parse_atom(depth);
  const Span minus = advance().span;
  if (check(TokenKind::Integer)) return integer(true, minus);
  const NodeIndex operand = parse_operand(depth + 1, "after '-'", &Parser::parse_unary);
  return node(NodeKind::Negate, Span::cover(minus, ast_.nodes[operand].span), operand);
}

NodeIndex Parser::integer(bool negated, Span minus) {
  const Token& t = advance();
  const Span span = negated ? Span::cover(minus, t.span) : t.span;
  const uint64_t limit = negated ? uint64_t{1} << 63 : static_cast<uint64_t>(INT64_MAX);
  int64_t value = 0;
  if (t.overflow || t.value > limit) report(span, "integer constant out of range (state variables are 64-bit signed)");
  else value = negated ? static_cast<int64_t>(0 - t.value) : static_cast<int64_t>(t.value);
  const NodeIndex n = node(NodeKind::Integer, span);
  ast_.nodes[n].value = value;
  return n;
}

// atom := INT | statevar | '(' expr ')' | 'abs' '(' expr ')' | ('min' | 'max') '(' expr ',' expr ')'
//       | aggregate | 'times' '[' INT ']' '(' or ')' | 'id' '(' module ')'  (aggregates: argmin, argmax too)
NodeIndex Parser::parse_atom(int depth) {
  const Span start = peek().span;
  switch (peek().kind) {
    case TokenKind::Integer: return integer(false, {});
    case TokenKind::NonInteger:
      error_at(start, "non-integer constant '" + std::string(source_.slice(start)) + "': state variables are integers");
      advance();
      return error_node(start);
    case TokenKind::Name: return parse_statevar();
    case TokenKind::LParen: {
      advance();
      const NodeIndex inner = parse_operand(depth + 1, "after '('");
      if (panic_) return skip_group(start);
      if (!match(TokenKind::RParen)) {
        if (check(TokenKind::End)) error_at(start, "'(' is never closed");
        else error_expected("')' or an operator");
        return skip_group(start);
      }
      ast_.nodes[inner].span = Span::cover(start, previous().span);
      return inner;
    }
    case TokenKind::Abs: {
      advance();
      if (!expect(TokenKind::LParen, "'(' after 'abs'")) return error_node(start);
      const NodeIndex operand = parse_operand(depth + 1, "in abs()");
      if (panic_ || !expect(TokenKind::RParen, "')' after the operand of abs()")) return skip_group(start);
      return node(NodeKind::Abs, Span::cover(start, previous().span), operand);
    }
    case TokenKind::Min:
    case TokenKind::Max:
      if (at(pos_ + 3).kind == TokenKind::In) return parse_aggregate(depth);  // min ( NAME in
      return parse_min_max(depth);
    case TokenKind::Count:
    case TokenKind::Sum:
    case TokenKind::Argmin:
    case TokenKind::Argmax: return parse_aggregate(depth);
    case TokenKind::Times: return parse_window(depth);
    case TokenKind::Id: return parse_id();
    default: error_expected("a number, a state variable or an expression"); return error_node(start);
  }
}

NodeIndex Parser::parse_min_max(int depth) {
  const Token& kw = advance();
  const Span start = kw.span;
  const bool is_min = kw.kind == TokenKind::Min;
  const std::string name = is_min ? "min" : "max";
  if (!expect(TokenKind::LParen, "'(' after '" + name + "'")) return error_node(start);
  const NodeIndex a = parse_operand(depth + 1, "in " + name + "()");
  if (panic_ ||
      !expect(TokenKind::Comma, "',' between the two operands of " + name + "() (or 'NAME in neighbors(...)')"))
    return skip_group(start);
  const NodeIndex b = parse_operand(depth + 1, "after ','");
  if (panic_ || !expect(TokenKind::RParen, "')' after the two operands of " + name + "()")) return skip_group(start);
  return node(is_min ? NodeKind::Min : NodeKind::Max, Span::cover(start, previous().span), a, b);
}

// aggregate := 'count' '(' NAME 'in' domain [':' or] ')'
//            | ('sum' | 'min' | 'max' | 'argmin' | 'argmax') '(' NAME 'in' domain ':' expr ')'
NodeIndex Parser::parse_aggregate(int depth) {
  const Token& kw = advance();
  Node n;
  n.kind = NodeKind::Aggregate;
  n.aggregate = kw.kind == TokenKind::Count    ? AggregateKind::Count
                : kw.kind == TokenKind::Sum    ? AggregateKind::Sum
                : kw.kind == TokenKind::Min    ? AggregateKind::Min
                : kw.kind == TokenKind::Max    ? AggregateKind::Max
                : kw.kind == TokenKind::Argmin ? AggregateKind::Argmin
                                               : AggregateKind::Argmax;
  const std::string what = aggregate_name(n.aggregate);
  const Span start = kw.span;
  if (!expect(TokenKind::LParen, "'(' after '" + what + "'")) return error_node(start);
  if (!check(TokenKind::Name)) {
    if (is_keyword(peek().kind)) error_at(peek().span, "keyword " + describe(peek().kind) + " cannot be a bound name");
    else error_expected("a name for each neighbour, as in '" + what + "(n in neighbors(a)...)'");
    return skip_group(start);
  }
  const Token& bound = advance();
  n.name = std::string(source_.slice(bound.span));
  bool bad_name = false;
  for (const SlotDecl& s : ast_.slots)
    if (s.name == n.name) {
      report(bound.span, "bound name '" + n.name + "' shadows module '" + n.name + "': name each neighbour otherwise");
      bad_name = true;
    }
  const bool nested = !bound_.empty();
  if (nested) report(Span::cover(start, bound.span), "aggregates do not nest: this one is inside '" + bound_ + "''s");
  if (!expect(TokenKind::In, "'in' after the bound name '" + n.name + "'")) return skip_group(start);
  if (!parse_domain(n, bad_name, nested, depth)) return skip_group(start);
  const std::string saved = bound_;
  if (!nested) bound_ = bad_name ? std::string() : n.name;
  bound_names_.push_back(n.name);
  const size_t body_begin = ast_.nodes.size();
  if (match(TokenKind::Colon)) {
    if (n.aggregate == AggregateKind::Count) {
      n.lhs = parse_or(depth + 1);
    } else {
      n.lhs = parse_operand(depth + 1, "after ':'");
    }
  } else if (n.aggregate != AggregateKind::Count) {
    error_expected("':' and the value to take of each neighbour, as in '" + what + "(n in neighbors(a): n.x)'");
  }
  bound_ = saved;
  // A neighbour is read at the domain's offset plus its own: the limit holds for the sum (a read
  // of 'n.next' 10,000 times over 'neighbors(a.next...)' 10,000 times looks 20,000 steps ahead).
  for (size_t i = body_begin; i < ast_.nodes.size() && !offset_reported_; ++i) {
    const Node& read = ast_.nodes[i];
    if (read.kind != NodeKind::Variable || !read.x.bound) continue;
    const int64_t offset = int64_t{n.x.offset} + read.x.offset;
    if (std::abs(offset) <= kMaxOffset) continue;
    offset_reported_ = true;
    report(read.span, "this read of a neighbour is " + std::to_string(std::abs(offset)) + " steps " +
                          (offset < 0 ? "back" : "ahead") + " (its domain's offset plus its own): a watchpoint looks " +
                          "at most " + std::to_string(kMaxOffset) + " steps back or ahead");
  }
  if (bail_) return error_node(start);
  if (panic_ || !expect(TokenKind::RParen, "')' to close '" + what + "('")) return skip_group(start);
  n.span = Span::cover(start, previous().span);
  return add(std::move(n));
}

// domain := 'neighbors' '(' module ')' | 'within' '(' module ',' INT ')' | 'all'
//         | 'component' '(' module ':' or ')'
// On a mistake, said once, false: the caller skips to the aggregate's ')' (this skips to the domain's).
bool Parser::parse_domain(Node& n, bool& bad_name, bool nested, int depth) {
  if (match(TokenKind::All)) {
    n.domain = Domain::All;
    n.x.slot = 0;  // the match step is slot 0's "now" (ast.h)
    n.x.span = previous().span;
    return true;
  }
  if (!check(TokenKind::Neighbors) && !check(TokenKind::Within) && !check(TokenKind::Component)) {
    error_expected("'neighbors(m)', 'within(m, h)', 'all' or 'component(m: c)' after 'in'");
    return false;
  }
  const TokenKind kind = advance().kind;
  const bool within = kind == TokenKind::Within;
  const std::string word = within ? "within" : kind == TokenKind::Component ? "component" : "neighbors";
  n.domain = within ? Domain::Within : kind == TokenKind::Component ? Domain::Component : Domain::Neighbors;
  if (!expect(TokenKind::LParen, "'(' after '" + word + "'")) return false;
  const Span open = previous().span;
  auto fail = [&] {  // inside its '(': up to its ')' first
    skip_group(open);
    return false;
  };
  // A bound name that shadows a module was said already: it names that module here.
  if (!bad_name && check(TokenKind::Name) && source_.slice(peek().span) == n.name) {
    report(peek().span, "an aggregate ranges over a module's " + std::string(within ? "surroundings" : "neighbours") +
                            "; '" + n.name + "' is its own bound name, not a module");
    bad_name = true;
    quiet_ = n.name;  // said once: not "undeclared" as well
  }
  const bool parsed = parse_module_in_neighbor(n.x, (word + "()").c_str());
  quiet_.clear();
  if (!parsed) return fail();
  if (within) {
    if (!expect(TokenKind::Comma, "',' and the number of hops after the module, as in 'within(a, 2)'")) return fail();
    const Token h = peek();
    if (h.kind != TokenKind::Integer) {
      error_expected("the number of hops, 1 to " + std::to_string(kMaxWithinHops));
      return fail();
    }
    advance();
    if (h.overflow || h.value < 1 || h.value > static_cast<uint64_t>(kMaxWithinHops))
      report(h.span, "within(m, h) reaches 1 to " + std::to_string(kMaxWithinHops) + " hops");
    else n.value = static_cast<int64_t>(h.value);
  }
  if (n.domain == Domain::Component) {
    if (!expect(TokenKind::Colon, "':' and the condition a member meets, as in 'component(a: n.c = a.c)'"))
      return fail();
    // The condition is over the bound name, the candidate (no aggregate inside: they do not nest).
    const std::string saved = bound_;
    if (!nested) bound_ = bad_name ? std::string() : n.name;
    n.rhs = parse_or(depth + 1);
    bound_ = saved;
    if (bail_ || panic_) return fail();
  }
  if (!expect(TokenKind::RParen, "')' after the module of " + word + "()")) return fail();
  if (n.x.bound) report(n.x.span, "an aggregate ranges over a module of modules(...), not over a bound name");
  return true;
}

// ---- modules and state variables ----------------------------------------------------------

// One 'last' (-1) or 'next' (+1) more on `m`. Past kMaxOffset: one error for the chain, which
// is still read to its end (in linear time) so that parsing goes on after it.
void Parser::shift(ModuleRef& m, int delta) {
  if (std::abs(m.offset + delta) <= kMaxOffset) {
    m.offset += delta;
    return;
  }
  if (std::abs(m.offset) == kMaxOffset && !offset_reported_) {
    offset_reported_ = true;
    report(Span::cover(m.span, previous().span), "temporal offset past " + std::to_string(kMaxOffset) +
                                                     " steps: a watchpoint looks at most " +
                                                     std::to_string(kMaxOffset) + " steps back or ahead");
  }
}

// module := NAME ('.' ('last' | 'next'))*
bool Parser::parse_module_in_neighbor(ModuleRef& out, const char* taker) {
  if (!parse_slot_name(out)) return false;
  while (match(TokenKind::Dot)) {
    if (match(TokenKind::Last)) shift(out, -1);
    else if (match(TokenKind::Next)) shift(out, +1);
    else {
      error_at(peek().span, std::string(taker) + " takes modules, not variables: expected 'last' or 'next' after '.'");
      return false;
    }
    out.span = Span::cover(out.span, previous().span);
  }
  return true;
}

// A declared slot, or inside an aggregate its bound name.
bool Parser::parse_slot_name(ModuleRef& out) {
  if (!check(TokenKind::Name)) {
    if (is_keyword(peek().kind)) error_at(peek().span, "keyword " + describe(peek().kind) + " cannot be a module name");
    else error_expected("a module name");
    return false;
  }
  const Token& t = advance();
  out.span = t.span;
  const std::string name(source_.slice(t.span));
  if (!bound_.empty() && name == bound_) {
    out.bound = true;
    return true;
  }
  for (size_t i = 0; i < ast_.slots.size(); ++i)
    if (ast_.slots[i].name == name) out.slot = static_cast<int32_t>(i);
  if (out.slot >= 0) return true;
  if (name == quiet_) return true;
  for (const std::string& b : bound_names_)
    if (b == name) {
      report(t.span, "'" + name + "' is a bound name, known only inside its aggregate");
      return true;
    }
  std::string declared;
  for (const SlotDecl& s : ast_.slots) declared += (declared.empty() ? "" : " ") + s.name;
  report(t.span, "module '" + name + "' is not declared in modules(" + declared + ")");
  return true;
}

// A variable's name after '.': a name, or a keyword of expressions (`a.count`).
bool Parser::parse_variable_name(std::string& out) {
  if (check(TokenKind::Name) || (is_keyword(peek().kind) && !is_reserved(peek().kind))) {
    out = std::string(source_.slice(advance().span));
    return true;
  }
  if (is_keyword(peek().kind)) {
    error_at(peek().span, "keyword " + describe(peek().kind) + " cannot be a variable name");
    advance();  // so that recovery does not take the keyword for an operator
  } else {
    error_expected("a variable name after '.'");
  }
  return false;
}

// statevar := module '.' NAME      -- module := NAME ('.' ('last' | 'next'))*
NodeIndex Parser::parse_statevar() {
  Node n;
  n.kind = NodeKind::Variable;
  const Span start = peek().span;
  if (check(TokenKind::Name) && at(pos_ + 1).kind == TokenKind::LParen) {
    // A call of no function the language has (a misspelt 'min'): one mistake, said once.
    error_at(start, "'" + std::string(source_.slice(start)) +
                        "' is no function; the language's are count, sum, min, max, abs, argmin, argmax, id, "
                        "once, historically, since and times");
    advance();  // the name
    advance();  // '('
    return skip_group(start);
  }
  if (!parse_slot_name(n.x)) return error_node(start);
  for (;;) {
    if (!match(TokenKind::Dot)) {
      const std::string m = std::string(source_.slice(n.x.span));
      if (n.x.offset != 0) {
        const std::string kw = previous().kind == TokenKind::Last ? "last" : "next";
        error_at(previous().span, "'" + kw + "' is a keyword, not a variable: '" + m +
                                      "' is a module at an offset; write '" + m + ".VARIABLE'");
      } else {
        error_expected("'.' and a variable name after '" + m + "'");
      }
      return error_node(start);
    }
    if (match(TokenKind::Last)) {
      shift(n.x, -1);
    } else if (match(TokenKind::Next)) {
      shift(n.x, +1);
    } else {
      if (!parse_variable_name(n.name)) return error_node(start);
      n.span = Span::cover(start, previous().span);
      return add(std::move(n));
    }
    n.x.span = Span::cover(n.x.span, previous().span);
  }
}

}  // namespace dw::watch::detail
