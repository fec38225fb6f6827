// The watchpoint parser's state and plumbing (watch/parser.h is its interface): a recursive-descent
// parser with panic-mode recovery, its grammar split over parser.cpp and parse_expression.cpp.
// Internal to watch/.
#pragma once

#include <cstdint>
#include <deque>
#include <string>
#include <unordered_map>
#include <vector>

#include "watch/lexer.h"
#include "watch/parser.h"

namespace dw::watch::detail {

bool starts_expression(TokenKind k);
bool starts_window_condition(TokenKind k);  // once, historically, since

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
  // speculative parse (a '(' being decided, see opens_condition) may come back to them, so a parser
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
  // balancing any opened on the way, and past it. The error stays in force for the caller. Past
  // the nesting limit the rest is abandoned unread: each of the 256 groups open would otherwise
  // read the rest of the input (4 MB of '(' took 35 s).
  NodeIndex skip_group(Span start) {
    if (bail_) return error_node(start);
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

  // The grammar: parser.cpp has the watchpoint, its actions and conditions; parse_expression.cpp
  // the integer expressions (docs/design.md §4b), modules and variables.
  void parse_watchpoint();
  bool parse_module_decl();
  void parse_actions();
  bool parse_action_slot(ModuleRef& out, const char* verb);
  NodeIndex parse_or(int depth);
  NodeIndex parse_and(int depth);
  NodeIndex binary(NodeKind kind, NodeIndex l, NodeIndex r);
  NodeIndex parse_not(int depth);
  NodeIndex parse_primary(int depth);
  bool opens_condition(int depth);

  // What a speculative parse (opens_condition) rolls back.
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

  NodeIndex parse_neighbor(Span keyword);
  // Windows in time and id() (docs/design.md §4c), in watch/parse_window.cpp.
  NodeIndex parse_window(int depth);
  bool parse_window_length(Node& n, const std::string& what);
  void check_reach(NodeIndex window);
  void check_one_module(NodeIndex since);
  NodeIndex parse_id();

  std::string name_of(const ModuleRef& m) const { return m.bound ? bound_ : ast_.slots[m.slot].name; }
  std::string module_text(const ModuleRef& m) const { return std::string(source_.slice(m.span)); }

  NodeIndex parse_compare(int depth);

  // ---- grammar: integer expressions (docs/design.md §4b) --------------------------------------------

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

  NodeIndex parse_expr(int depth);
  NodeIndex parse_mul(int depth);
  NodeIndex parse_unary(int depth);
  NodeIndex integer(bool negated, Span minus);
  NodeIndex parse_atom(int depth);
  NodeIndex parse_min_max(int depth);
  NodeIndex parse_aggregate(int depth);
  bool parse_domain(Node& n, bool& bad_name, bool nested, int depth);
  void shift(ModuleRef& m, int delta);
  bool parse_module_in_neighbor(ModuleRef& out, const char* taker = "neighbor()");
  bool parse_slot_name(ModuleRef& out);
  bool parse_variable_name(std::string& out);
  NodeIndex parse_statevar();

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

}  // namespace dw::watch::detail
