#include "watch/parser.h"

#include <array>
#include <cstdlib>
#include <string>

#include "watch/lexer.h"

namespace dw::watch {
namespace {

class Parser {
 public:
  explicit Parser(const SourceText& source) : source_(source), tokens_(source) {}

  ParseResult run() {
    parse_watchpoint();
    return {std::move(ast_), std::move(diagnostics_)};
  }

 private:
  // ---- token stream -------------------------------------------------------------------------

  // Tokens are lexed as the parser reaches them and kept in a small ring: the parser looks at most
  // one token back and one ahead, and holds no reference to a token across more than a few.
  const Token& at(size_t i) const {
    while (lexed_ <= i) ring_[lexed_++ % kRing] = tokens_.next();
    return ring_[i % kRing];
  }
  const Token& peek() const { return at(pos_); }
  const Token& previous() const { return at(pos_ - 1); }
  bool check(TokenKind k) const { return peek().kind == k; }
  const Token& advance() {
    if (!check(TokenKind::End)) ++pos_;
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

  // Skips to a token that can follow a primary at the current depth: `and`, `or`, the `)` that
  // closes the enclosing group, or the end. Parentheses opened while skipping are balanced.
  void synchronize() {
    int depth = 0;
    while (!check(TokenKind::End)) {
      const TokenKind k = peek().kind;
      if (depth == 0 && (k == TokenKind::And || k == TokenKind::Or || k == TokenKind::RParen)) break;
      if (k == TokenKind::LParen) ++depth;
      if (k == TokenKind::RParen) --depth;
      advance();
    }
    panic_ = false;
  }

  NodeIndex add(Node n) {
    if (ast_.nodes.size() >= kMaxNodes) {
      if (!too_large_)
        report(n.span, "watchpoint too large: more than " + std::to_string(kMaxNodes) +
                           " terms (comparisons, neighbor() tests, 'not's, and one per 'and'/'or')");
      too_large_ = true;
      bail_ = true;
    }
    ast_.nodes.push_back(std::move(n));
    return static_cast<NodeIndex>(ast_.nodes.size() - 1);
  }

  NodeIndex error_node(Span span) {
    Node n;
    n.kind = NodeKind::Error;
    n.span = span;
    return add(std::move(n));
  }

  // ---- grammar ------------------------------------------------------------------------------

  // watchpoint := 'modules' '(' NAME (','? NAME)* ')' ';' or END
  void parse_watchpoint() {
    parse_module_decl();
    // Without module names every name below would be "undeclared": one mistake, one message.
    if (ast_.slots.empty()) return;
    if (!match(TokenKind::Semicolon)) {
      // Going on is only useful when the expression clearly starts here.
      if (check(TokenKind::LParen) || check(TokenKind::Not) || check(TokenKind::Neighbor) || check(TokenKind::Name)) {
        error_expected("';' after the module list");
        panic_ = false;
      } else {
        error_expected("';' after the module list");
        return;
      }
    }
    if (check(TokenKind::End)) {
      const uint32_t after = previous().span.end;
      error_at({after, after}, "expected a condition after ';'");
      return;
    }
    ast_.root = parse_or(0);
    if (bail_) return;
    if (!check(TokenKind::End)) {
      if (check(TokenKind::RParen)) error_at(peek().span, "unmatched ')'");
      else error_expected("'and', 'or' or end of input");
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

  // or := and ('or' and)*
  NodeIndex parse_or(int depth) {
    NodeIndex left = parse_and(depth);
    while (!bail_ && match(TokenKind::Or)) {
      NodeIndex right = parse_and(depth);
      left = binary(NodeKind::Or, left, right);
    }
    return left;
  }

  // and := not ('and' not)*
  NodeIndex parse_and(int depth) {
    NodeIndex left = parse_not(depth);
    while (!bail_ && match(TokenKind::And)) {
      NodeIndex right = parse_not(depth);
      left = binary(NodeKind::And, left, right);
    }
    return left;
  }

  NodeIndex binary(NodeKind kind, NodeIndex l, NodeIndex r) {
    Node n;
    n.kind = kind;
    n.span = Span::cover(ast_.nodes[l].span, ast_.nodes[r].span);
    n.lhs = l;
    n.rhs = r;
    return add(std::move(n));
  }

  // not := 'not' not | primary
  NodeIndex parse_not(int depth) {
    if (!enter(depth)) return error_node(peek().span);
    if (check(TokenKind::Not)) {
      const Span kw = advance().span;
      NodeIndex operand = parse_not(depth + 1);
      Node n;
      n.kind = NodeKind::Not;
      n.span = Span::cover(kw, ast_.nodes[operand].span);
      n.lhs = operand;
      return add(std::move(n));
    }
    return parse_primary(depth);
  }

  // Guards recursion: past kMaxNesting the rest of the input is abandoned with one error.
  bool enter(int depth) {
    if (bail_) return false;
    if (depth < kMaxNesting) return true;
    report(peek().span, "expression nested too deeply (more than " + std::to_string(kMaxNesting) + " levels)");
    bail_ = true;
    panic_ = true;
    return false;
  }

  // primary := 'neighbor' '(' module ','? module ')' | '(' or ')' | compare
  // The paper's `'(' compare ')'` is the case of `'(' or ')'` whose inside is one comparison; a
  // bare comparison where a primary is expected is an accepted extension.
  NodeIndex parse_primary(int depth) {
    const Span start = peek().span;
    if (match(TokenKind::Neighbor)) return parse_neighbor(start);
    if (match(TokenKind::LParen)) {
      NodeIndex inner = parse_or(depth + 1);
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
      return inner;
    }
    if (check(TokenKind::Name)) return parse_compare();
    if (check(TokenKind::Integer) || check(TokenKind::NonInteger)) {
      error_at(peek().span, "a comparison must start with a state variable such as 'a.x', not a constant");
    } else {
      error_expected("a condition ('(', 'not', 'neighbor' or a comparison)");
    }
    synchronize();
    return error_node(start);
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
    if (n.x.slot >= 0 && n.y.slot >= 0) {
      if (n.x.slot == n.y.slot) {
        report(n.span, "neighbor() needs two different modules; '" + ast_.slots[n.x.slot].name +
                           "' is never its own neighbour");
      } else if (n.x.offset != n.y.offset) {
        report(n.span, "neighbor() compares two modules at the same step, but '" + to_string(ast_, n.x) +
                           "' is at offset " + std::to_string(n.x.offset) + " and '" + to_string(ast_, n.y) +
                           "' at offset " + std::to_string(n.y.offset));
      }
    }
    return add(std::move(n));
  }

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
    for (size_t i = 0; i < ast_.slots.size(); ++i)
      if (ast_.slots[i].name == name) out.slot = static_cast<int32_t>(i);
    if (out.slot < 0) {
      std::string declared;
      for (const SlotDecl& s : ast_.slots) declared += (declared.empty() ? "" : " ") + s.name;
      report(t.span, "module '" + name + "' is not declared in modules(" + declared + ")");
    }
    return true;
  }

  // statevar := module '.' NAME      -- module := NAME ('.' ('last' | 'next'))*
  bool parse_statevar(Operand& out) {
    if (!parse_slot_name(out.module)) return false;
    for (;;) {
      if (!match(TokenKind::Dot)) {
        const std::string m = std::string(source_.slice(out.module.span));
        if (out.module.offset != 0) {
          const std::string kw = previous().kind == TokenKind::Last ? "last" : "next";
          error_at(previous().span, "'" + kw + "' is a keyword, not a variable: '" + m +
                                        "' is a module at an offset; write '" + m + ".VARIABLE'");
        } else {
          error_expected("'.' and a variable name after '" + m + "'");
        }
        return false;
      }
      if (match(TokenKind::Last)) {
        shift(out.module, -1);
      } else if (match(TokenKind::Next)) {
        shift(out.module, +1);
      } else if (check(TokenKind::Name)) {
        const Token& t = advance();
        out.variable = std::string(source_.slice(t.span));
        out.span = Span::cover(out.module.span, t.span);
        return true;
      } else if (is_keyword(peek().kind)) {
        error_at(peek().span, "keyword " + describe(peek().kind) + " cannot be a variable name");
        advance();  // so that recovery does not take the keyword for an operator
        return false;
      } else {
        error_expected("a variable name after '.'");
        return false;
      }
      out.module.span = Span::cover(out.module.span, previous().span);
    }
  }

  // compare := statevar OP rval          rval := statevar | INT
  NodeIndex parse_compare() {
    Node n;
    n.kind = NodeKind::Compare;
    const Span start = peek().span;
    if (!parse_statevar(n.left)) {
      synchronize();
      return error_node(start);
    }
    if (!is_comparison(peek().kind)) {
      error_expected("a comparison operator (<, >, =, !=, >=, <=) after '" + to_string_lhs(n.left) + "'");
      synchronize();
      return error_node(start);
    }
    n.op = static_cast<CompareOp>(static_cast<int>(advance().kind) - static_cast<int>(TokenKind::Less));
    if (check(TokenKind::Integer)) {
      const Token& t = advance();
      if (t.overflow) report(t.span, "integer constant out of range (state variables are 64-bit signed)");
      n.right.is_constant = true;
      n.right.constant = t.value;
      n.right.span = t.span;
    } else if (check(TokenKind::NonInteger)) {
      error_at(peek().span,
               "non-integer constant '" + std::string(source_.slice(peek().span)) + "': state variables are integers");
      advance();
      panic_ = false;
      return error_node(start);
    } else if (check(TokenKind::Name)) {
      if (!parse_statevar(n.right)) {
        synchronize();
        return error_node(start);
      }
    } else {
      error_expected("a number or a state variable after '" + std::string(spelling(n.op)) + "'");
      synchronize();
      return error_node(start);
    }
    n.span = Span::cover(n.left.span, n.right.span);
    return add(std::move(n));
  }

  std::string to_string_lhs(const Operand& o) const { return std::string(source_.slice(o.span)); }

  const SourceText& source_;
  static constexpr size_t kRing = 8;
  mutable TokenStream tokens_;
  mutable std::array<Token, kRing> ring_;
  mutable size_t lexed_ = 0;  // tokens lexed so far; token i is in ring_[i % kRing]
  size_t pos_ = 0;
  Ast ast_;
  std::vector<Diagnostic> diagnostics_;
  bool panic_ = false;            // recovering from a syntax error: further syntax errors are cascades
  bool offset_reported_ = false;  // one error for offsets out of range, however many there are
  bool bail_ = false;             // nesting or size limit hit: stop parsing
  bool too_large_ = false;
  bool too_many_slots_ = false;
};

}  // namespace

ParseResult parse(const SourceText& source) { return Parser(source).run(); }

}  // namespace dw::watch
