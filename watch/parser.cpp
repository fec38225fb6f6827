#include "watch/parser.h"

#include <cstdlib>
#include <deque>
#include <string>
#include <unordered_map>

#include "watch/lexer.h"

namespace dw::watch {
namespace {

bool starts_expression(TokenKind k) {
  return k == TokenKind::Name || k == TokenKind::Integer || k == TokenKind::NonInteger || k == TokenKind::Minus ||
         k == TokenKind::LParen || k == TokenKind::Abs || k == TokenKind::Min || k == TokenKind::Max ||
         k == TokenKind::Count || k == TokenKind::Sum;
}

class Parser {
 public:
  explicit Parser(const SourceText& source) : source_(source), tokens_(source) {}

  ParseResult run() {
    parse_watchpoint();
    return {std::move(ast_), std::move(diagnostics_)};
  }

 private:
  // ---- token stream -------------------------------------------------------------------------

  // Tokens are lexed as the parser reaches them. Those behind the parser are dropped unless a
  // speculative parse (a '(' being decided, see parse_group) may come back to them, so a parser
  // holds a few tokens however long the input.
  const Token& at(size_t i) const {
    while (lexed_ <= i) {
      buffer_.push_back(tokens_.next());
      ++lexed_;
    }
    return buffer_[i - base_];
  }
  const Token& peek() const { return at(pos_); }
  const Token& previous() const { return at(pos_ - 1); }
  bool check(TokenKind k) const { return peek().kind == k; }
  const Token& advance() {
    if (!check(TokenKind::End)) ++pos_;
    if (marks_ == 0)
      while (pos_ - base_ > 8) buffer_.pop_front(), ++base_;
    return previous();
  }
  bool match(TokenKind k) {
    if (!check(k)) return false;
    advance();
    return true;
  }

  // ---- diagnostics --------------------------------------------------------------------------

  // A syntax error: reported unless we are already recovering from one.
  void error_at(Span span, std::string message) {
    if (panic_) return;
    panic_ = true;
    if (syntax_error_at_ == kNone) syntax_error_at_ = span.begin;
    report(span, std::move(message));
  }

  // A semantic error (undeclared name, bad neighbor()): the syntax is fine, so no recovery needed.
  void report(Span span, std::string message) { diagnostics_.push_back({span, std::move(message)}); }

  // "expected X, found Y", pointing at the offending token; invalid tokens say why they are invalid.
  void error_expected(const std::string& what) {
    const Token& t = peek();
    if (t.kind == TokenKind::Invalid) {
      error_at(t.span, t.message);
    } else if (t.kind == TokenKind::End) {
      error_at(t.span, "expected " + what + " before end of input");
    } else {
      error_at(t.span, "expected " + what + ", found " + found(t));
    }
  }

  std::string found(const Token& t) const {
    if (t.kind == TokenKind::Name || t.kind == TokenKind::Integer || t.kind == TokenKind::NonInteger)
      return "'" + std::string(source_.slice(t.span)) + "'";
    return describe(t.kind);
  }

  bool expect(TokenKind k, const std::string& what) {
    if (match(k)) return true;
    error_expected(what);
    return false;
  }

  // Skips to a token that can follow a primary at the current depth: `and`, `or`, `then`, the `)`
  // that closes the enclosing group, or the end. Parentheses opened while skipping are balanced.
  void synchronize() {
    int depth = 0;
    while (!check(TokenKind::End)) {
      const TokenKind k = peek().kind;
      if (depth == 0 && (k == TokenKind::And || k == TokenKind::Or || k == TokenKind::RParen || k == TokenKind::Then))
        break;
      if (k == TokenKind::LParen) ++depth;
      if (k == TokenKind::RParen) --depth;
      advance();
    }
    panic_ = false;
  }

  // After a syntax error inside parentheses this parser opened: skips to the ')' that closes them,
  // balancing any opened on the way, and past it. The error stays in force for the caller.
  NodeIndex skip_group(Span start) {
    int depth = 0;
    while (!check(TokenKind::End)) {
      const TokenKind k = advance().kind;
      if (k == TokenKind::LParen) ++depth;
      if (k == TokenKind::RParen && depth-- == 0) break;
    }
    return error_node(start);
  }

  NodeIndex add(Node n) {
    if (ast_.nodes.size() >= kMaxNodes) {
      if (!too_large_)
        report(n.span, "watchpoint too large: more than " + std::to_string(kMaxNodes) +
                           " terms (comparisons, neighbor() tests, 'not's, operators and operands)");
      too_large_ = true;
      bail_ = true;
    }
    ast_.nodes.push_back(std::move(n));
    return static_cast<NodeIndex>(ast_.nodes.size() - 1);
  }

  NodeIndex node(NodeKind kind, Span span, NodeIndex lhs = kNoNode, NodeIndex rhs = kNoNode) {
    Node n;
    n.kind = kind;
    n.span = span;
    n.lhs = lhs;
    n.rhs = rhs;
    return add(std::move(n));
  }

  NodeIndex error_node(Span span) { return node(NodeKind::Error, span); }

  // Guards recursion: past kMaxNesting the rest of the input is abandoned with one error.
  bool enter(int depth) {
    if (bail_) return false;
    if (depth < kMaxNesting) return true;
    report(peek().span, "expression nested too deeply (more than " + std::to_string(kMaxNesting) + " levels)");
    bail_ = true;
    panic_ = true;
    return false;
  }

  // ---- grammar: the watchpoint --------------------------------------------------------------

  // watchpoint := 'modules' '(' NAME (','? NAME)* ')' ';' or ['then' action (',' action)*] END
  void parse_watchpoint() {
    parse_module_decl();
    // Without module names every name below would be "undeclared": one mistake, one message.
    if (ast_.slots.empty()) return;
    if (!match(TokenKind::Semicolon)) {
      error_expected("';' after the module list");
      // Going on is only useful when the condition clearly starts here.
      if (!check(TokenKind::Not) && !check(TokenKind::Neighbor) && !starts_expression(peek().kind)) return;
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

  // module-decl := 'modules' '(' NAME (','? NAME)* ')'
  void parse_module_decl() {
    if (!check(TokenKind::Modules)) {
      error_expected("'modules(...)' at the start of a watchpoint");
      // Recover only if the declaration is just misspelled: NAME '(' ...
      if (!(check(TokenKind::Name) && at(pos_ + 1).kind == TokenKind::LParen)) return;
      panic_ = false;
    }
    advance();
    if (!expect(TokenKind::LParen, "'(' after 'modules'")) return;
    const Span open = previous().span;
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
      } else {
        error_expected(ast_.slots.empty() ? "a module name" : "a module name or ')'");
        while (!check(TokenKind::End) && !check(TokenKind::RParen) && !check(TokenKind::Semicolon)) advance();
        match(TokenKind::RParen);
        panic_ = false;
        return;
      }
    }
    advance();  // ')'
    if (ast_.slots.empty()) report(Span::cover(open, previous().span), "'modules()' must name at least one module");
  }

  // actions := 'then' action (',' action)*
  // action  := 'set' NAME '.' NAME '=' expr | 'remove' NAME
  void parse_actions() {
    advance();  // 'then'
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
  bool parse_action_slot(ModuleRef& out, const char* verb) {
    if (!check(TokenKind::Name)) {
      if (is_keyword(peek().kind))
        error_at(peek().span, "keyword " + describe(peek().kind) + " cannot be a module name");
      else error_expected(std::string("the module to ") + verb);
      return false;
    }
    return parse_slot_name(out);
  }

  // ---- grammar: conditions ------------------------------------------------------------------

  // or := and ('or' and)*
  NodeIndex parse_or(int depth) {
    NodeIndex left = parse_and(depth);
    while (!bail_ && match(TokenKind::Or)) left = binary(NodeKind::Or, left, parse_and(depth));
    return left;
  }

  // and := not ('and' not)*
  NodeIndex parse_and(int depth) {
    NodeIndex left = parse_not(depth);
    while (!bail_ && match(TokenKind::And)) left = binary(NodeKind::And, left, parse_not(depth));
    return left;
  }

  NodeIndex binary(NodeKind kind, NodeIndex l, NodeIndex r) {
    return node(kind, Span::cover(ast_.nodes[l].span, ast_.nodes[r].span), l, r);
  }

  // not := 'not' not | primary
  NodeIndex parse_not(int depth) {
    if (!enter(depth)) return error_node(peek().span);
    if (check(TokenKind::Not)) {
      const Span kw = advance().span;
      const NodeIndex operand = parse_not(depth + 1);
      return node(NodeKind::Not, Span::cover(kw, ast_.nodes[operand].span), operand);
    }
    return parse_primary(depth);
  }

  // primary := 'neighbor' '(' module ','? module ')' | '(' or ')' | compare
  // The paper's `'(' compare ')'` is the case of `'(' or ')'` whose inside is one comparison; a
  // bare comparison where a primary is expected is an accepted extension. A '(' that does not open
  // a condition opens the first operand of a comparison (DESIGN §4b).
  NodeIndex parse_primary(int depth) {
    const Span start = peek().span;
    if (match(TokenKind::Neighbor)) return parse_neighbor(start);
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
    error_expected("a condition ('(', 'not', 'neighbor' or a comparison)");
    synchronize();
    return error_node(start);
  }

  // Whether the '(' here opens a condition: it does when its contents parse as one (an `or` up to
  // the matching ')'), and opens an integer expression otherwise. When neither parses, the reading
  // that got further decides, so that its error is the one reported. Both readings are tried
  // without a trace and the verdict kept by the '(' token, so that nested parentheses are
  // decided once each (the work stays quadratic in the nesting, never exponential).
  bool opens_condition(int depth) {
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

  struct Saved {
    size_t pos, nodes, diagnostics;
    bool panic, bail, too_large, offset_reported;
    uint32_t syntax_error_at;
  };
  Saved save() {
    Saved s{pos_,  ast_.nodes.size(), diagnostics_.size(), panic_,
            bail_, too_large_,        offset_reported_,    syntax_error_at_};
    panic_ = false;
    syntax_error_at_ = kNone;
    return s;
  }
  void restore(const Saved& s) {
    pos_ = s.pos;
    ast_.nodes.resize(s.nodes);
    diagnostics_.resize(s.diagnostics);
    panic_ = s.panic, bail_ = s.bail, too_large_ = s.too_large, offset_reported_ = s.offset_reported;
    syntax_error_at_ = s.syntax_error_at;
  }

  // neighbor := 'neighbor' '(' module ','? module ')'
  NodeIndex parse_neighbor(Span keyword) {
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
        report(n.span, "neighbor() compares two modules at the same step, but '" + module_text(n.x) +
                           "' is at offset " + std::to_string(n.x.offset) + " and '" + module_text(n.y) +
                           "' at offset " + std::to_string(n.y.offset));
      }
    }
    return add(std::move(n));
  }

  std::string name_of(const ModuleRef& m) const { return m.bound ? bound_ : ast_.slots[m.slot].name; }
  std::string module_text(const ModuleRef& m) const { return std::string(source_.slice(m.span)); }

  // compare := expr OP expr
  NodeIndex parse_compare(int depth) {
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

  // ---- grammar: integer expressions (DESIGN §4b) --------------------------------------------

  // An expression where one must follow `context` ("after '='"), by `parse` (a whole expression,
  // or the operand of an operator): says what was expected if none starts here.
  NodeIndex parse_operand(int depth, const std::string& context,
                          NodeIndex (Parser::*parse)(int) = &Parser::parse_expr) {
    if (!starts_expression(peek().kind)) {
      error_expected("a number, a state variable or an expression " + context);
      return error_node(peek().span);
    }
    return (this->*parse)(depth);
  }

  // expr := mul (('+' | '-') mul)*
  NodeIndex parse_expr(int depth) {
    NodeIndex left = parse_mul(depth);
    while (!panic_ && !bail_ && (check(TokenKind::Plus) || check(TokenKind::Minus))) {
      const TokenKind op = advance().kind;
      const NodeIndex right = parse_operand(depth, "after " + describe(op), &Parser::parse_mul);
      left = binary(op == TokenKind::Plus ? NodeKind::Add : NodeKind::Subtract, left, right);
    }
    return left;
  }

  // mul := unary (('*' | '/' | '%') unary)*
  NodeIndex parse_mul(int depth) {
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
  NodeIndex parse_unary(int depth) {
    if (!enter(depth)) return error_node(peek().span);
    if (!check(TokenKind::Minus)) return parse_atom(depth);
    const Span minus = advance().span;
    if (check(TokenKind::Integer)) return integer(true, minus);
    const NodeIndex operand = parse_operand(depth + 1, "after '-'", &Parser::parse_unary);
    return node(NodeKind::Negate, Span::cover(minus, ast_.nodes[operand].span), operand);
  }

  NodeIndex integer(bool negated, Span minus) {
    const Token& t = advance();
    const Span span = negated ? Span::cover(minus, t.span) : t.span;
    const uint64_t limit = negated ? uint64_t{1} << 63 : static_cast<uint64_t>(INT64_MAX);
    int64_t value = 0;
    if (t.overflow || t.value > limit)
      report(span, "integer constant out of range (state variables are 64-bit signed)");
    else value = negated ? static_cast<int64_t>(0 - t.value) : static_cast<int64_t>(t.value);
    const NodeIndex n = node(NodeKind::Integer, span);
    ast_.nodes[n].value = value;
    return n;
  }

  // atom := INT | statevar | '(' expr ')' | 'abs' '(' expr ')' | ('min' | 'max') '(' expr ',' expr ')'
  //       | aggregate
  NodeIndex parse_atom(int depth) {
    const Span start = peek().span;
    switch (peek().kind) {
      case TokenKind::Integer: return integer(false, {});
      case TokenKind::NonInteger:
        error_at(start,
                 "non-integer constant '" + std::string(source_.slice(start)) + "': state variables are integers");
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
      case TokenKind::Sum: return parse_aggregate(depth);
      default: error_expected("a number, a state variable or an expression"); return error_node(start);
    }
  }

  NodeIndex parse_min_max(int depth) {
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

  // aggregate := 'count' '(' NAME 'in' 'neighbors' '(' module ')' [':' or] ')'
  //            | ('sum' | 'min' | 'max') '(' NAME 'in' 'neighbors' '(' module ')' ':' expr ')'
  NodeIndex parse_aggregate(int depth) {
    const Token& kw = advance();
    Node n;
    n.kind = NodeKind::Aggregate;
    n.aggregate = kw.kind == TokenKind::Count ? AggregateKind::Count
                  : kw.kind == TokenKind::Sum ? AggregateKind::Sum
                  : kw.kind == TokenKind::Min ? AggregateKind::Min
                                              : AggregateKind::Max;
    const std::string what = aggregate_name(n.aggregate);
    const Span start = kw.span;
    if (!expect(TokenKind::LParen, "'(' after '" + what + "'")) return error_node(start);
    if (!check(TokenKind::Name)) {
      if (is_keyword(peek().kind))
        error_at(peek().span, "keyword " + describe(peek().kind) + " cannot be a bound name");
      else error_expected("a name for each neighbour, as in '" + what + "(n in neighbors(a)...)'");
      return skip_group(start);
    }
    const Token& bound = advance();
    n.name = std::string(source_.slice(bound.span));
    bool bad_name = false;
    for (const SlotDecl& s : ast_.slots)
      if (s.name == n.name) {
        report(bound.span,
               "bound name '" + n.name + "' shadows module '" + n.name + "': name each neighbour otherwise");
        bad_name = true;
      }
    const bool nested = !bound_.empty();
    if (nested) report(Span::cover(start, bound.span), "aggregates do not nest: this one is inside '" + bound_ + "''s");
    if (!expect(TokenKind::In, "'in' after the bound name '" + n.name + "'")) return skip_group(start);
    if (!expect(TokenKind::Neighbors, "'neighbors' after 'in'")) return skip_group(start);
    if (!expect(TokenKind::LParen, "'(' after 'neighbors'")) return skip_group(start);
    if (check(TokenKind::Name) && source_.slice(peek().span) == n.name) {
      report(peek().span,
             "an aggregate ranges over a module's neighbours; '" + n.name + "' is its own bound name, not a module");
      bad_name = true;
      quiet_ = n.name;  // said once: not "undeclared" as well
    }
    const bool parsed = parse_module_in_neighbor(n.x);
    quiet_.clear();
    if (!parsed || !expect(TokenKind::RParen, "')' after the module of neighbors()")) {
      skip_group(start);
      return skip_group(start);
    }
    if (n.x.bound) report(n.x.span, "an aggregate ranges over a module of modules(...), not over a bound name");
    const std::string saved = bound_;
    if (!nested) bound_ = bad_name ? std::string() : n.name;
    bound_names_.push_back(n.name);
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
    if (bail_) return error_node(start);
    if (panic_ || !expect(TokenKind::RParen, "')' to close '" + what + "('")) return skip_group(start);
    n.span = Span::cover(start, previous().span);
    return add(std::move(n));
  }

  // ---- modules and state variables ----------------------------------------------------------

  // One 'last' (-1) or 'next' (+1) more on `m`. Past kMaxOffset: one error for the chain, which
  // is still read to its end (in linear time) so that parsing goes on after it.
  void shift(ModuleRef& m, int delta) {
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
  bool parse_module_in_neighbor(ModuleRef& out) {
    if (!parse_slot_name(out)) return false;
    while (match(TokenKind::Dot)) {
      if (match(TokenKind::Last)) shift(out, -1);
      else if (match(TokenKind::Next)) shift(out, +1);
      else {
        error_at(peek().span, "neighbor() takes modules, not variables: expected 'last' or 'next' after '.'");
        return false;
      }
      out.span = Span::cover(out.span, previous().span);
    }
    return true;
  }

  // A declared slot, or inside an aggregate its bound name.
  bool parse_slot_name(ModuleRef& out) {
    if (!check(TokenKind::Name)) {
      if (is_keyword(peek().kind))
        error_at(peek().span, "keyword " + describe(peek().kind) + " cannot be a module name");
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
  bool parse_variable_name(std::string& out) {
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
  NodeIndex parse_statevar() {
    Node n;
    n.kind = NodeKind::Variable;
    const Span start = peek().span;
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

  static constexpr uint32_t kNone = UINT32_MAX;
  const SourceText& source_;
  mutable TokenStream tokens_;
  mutable std::deque<Token> buffer_;  // tokens [base_, lexed_)
  mutable size_t lexed_ = 0;
  size_t base_ = 0;
  int marks_ = 0;  // speculative parses under way: keep every token from where they started
  size_t pos_ = 0;
  Ast ast_;
  std::vector<Diagnostic> diagnostics_;
  std::unordered_map<size_t, bool> verdicts_;  // by a '(' token's index: whether it opens a condition
  std::string bound_;                          // the bound name in scope, inside an aggregate
  std::string quiet_;                          // a name already diagnosed where it stands
  std::vector<std::string> bound_names_;       // every bound name so far, for a helpful message
  uint32_t syntax_error_at_ = kNone;           // where the first syntax error was, since the last save
  bool panic_ = false;                         // recovering from a syntax error: further syntax errors are cascades
  bool offset_reported_ = false;               // one error for offsets out of range, however many there are
  bool bail_ = false;                          // nesting or size limit hit: stop parsing
  bool too_large_ = false;
  bool too_many_slots_ = false;
};

}  // namespace

ParseResult parse(const SourceText& source) { return Parser(source).run(); }

}  // namespace dw::watch
