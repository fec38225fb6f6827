#include "watch/lexer.h"

#include <string_view>

namespace dw::watch {
namespace {

bool is_name_start(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_name_char(char c) { return is_name_start(c) || is_digit(c); }

TokenKind keyword_or_name(std::string_view word) {
  if (word == "modules") return TokenKind::Modules;
  if (word == "not") return TokenKind::Not;
  if (word == "and") return TokenKind::And;
  if (word == "or") return TokenKind::Or;
  if (word == "neighbor") return TokenKind::Neighbor;
  if (word == "last") return TokenKind::Last;
  if (word == "next") return TokenKind::Next;
  if (word == "in") return TokenKind::In;
  if (word == "neighbors") return TokenKind::Neighbors;
  if (word == "count") return TokenKind::Count;
  if (word == "sum") return TokenKind::Sum;
  if (word == "min") return TokenKind::Min;
  if (word == "max") return TokenKind::Max;
  if (word == "abs") return TokenKind::Abs;
  if (word == "then") return TokenKind::Then;
  if (word == "set") return TokenKind::Set;
  if (word == "remove") return TokenKind::Remove;
  if (word == "once") return TokenKind::Once;
  if (word == "historically") return TokenKind::Historically;
  if (word == "since") return TokenKind::Since;
  if (word == "times") return TokenKind::Times;
  if (word == "id") return TokenKind::Id;
  if (word == "within") return TokenKind::Within;
  if (word == "all") return TokenKind::All;
  if (word == "argmin") return TokenKind::Argmin;
  if (word == "argmax") return TokenKind::Argmax;
  if (word == "component") return TokenKind::Component;
  return TokenKind::Name;
}

}  // namespace

bool is_name(std::string_view word) {
  if (word.empty() || word.size() > kMaxNameLength || !is_name_start(word[0])) return false;
  for (char c : word)
    if (!is_name_char(c)) return false;
  return !is_reserved(keyword_or_name(word));  // what a watchpoint reads after '.' (a.count, not a.and)
}

class Lexer {
 public:
  explicit Lexer(const SourceText& source) : text_(source.text()), base_(source.base()) {}

  Token token() {
    skip_space_and_comments();
    return next();
  }

 private:
  void skip_space_and_comments() {
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v') {
        ++pos_;
      } else if (c == '#') {
        while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
      } else {
        return;
      }
    }
  }

  Token make(TokenKind kind, size_t begin) {
    Token t;
    t.kind = kind;
    t.span = {static_cast<uint32_t>(base_ + begin), static_cast<uint32_t>(base_ + pos_)};
    return t;
  }

  Token invalid(size_t begin, std::string message) {
    Token t = make(TokenKind::Invalid, begin);
    t.message = std::move(message);
    return t;
  }

  // INT := digit+ ; a fraction or exponent makes it a NonInteger token. A sign is never part of
  // the number: `a.x -1` is a subtraction, and the parser folds a unary minus into a literal.
  Token number(size_t begin) {
    while (pos_ < text_.size() && is_digit(text_[pos_])) ++pos_;
    bool fractional = false;
    if (pos_ + 1 < text_.size() && text_[pos_] == '.' && is_digit(text_[pos_ + 1])) {
      fractional = true;
      ++pos_;
      while (pos_ < text_.size() && is_digit(text_[pos_])) ++pos_;
    }
    if (pos_ < text_.size() && (text_[pos_] == 'e' || text_[pos_] == 'E')) {
      size_t p = pos_ + 1;
      if (p < text_.size() && (text_[p] == '+' || text_[p] == '-')) ++p;
      if (p < text_.size() && is_digit(text_[p])) {
        fractional = true;
        pos_ = p;
        while (pos_ < text_.size() && is_digit(text_[pos_])) ++pos_;
      }
    }
    if (pos_ < text_.size() && is_name_char(text_[pos_])) {
      while (pos_ < text_.size() && is_name_char(text_[pos_])) ++pos_;
      return invalid(begin, "malformed number '" + std::string(text_.substr(begin, pos_ - begin)) + "'");
    }
    if (fractional) return make(TokenKind::NonInteger, begin);
    // The magnitude, up to 2^63: -9223372036854775808 is a literal 2^63 under a unary minus.
    constexpr uint64_t kLimit = uint64_t{1} << 63;
    Token t = make(TokenKind::Integer, begin);
    uint64_t acc = 0;
    for (size_t i = begin; i < pos_; ++i) {
      const uint64_t d = static_cast<uint64_t>(text_[i] - '0');
      if (acc > (kLimit - d) / 10) {
        t.overflow = true;
        break;
      }
      acc = acc * 10 + d;
    }
    t.value = acc;
    return t;
  }

  Token next() {
    const size_t begin = pos_;
    if (pos_ >= text_.size()) return make(TokenKind::End, begin);
    const char c = text_[pos_];
    if (is_name_start(c)) {
      while (pos_ < text_.size() && is_name_char(text_[pos_])) ++pos_;
      return make(keyword_or_name(text_.substr(begin, pos_ - begin)), begin);
    }
    if (is_digit(c)) return number(begin);
    ++pos_;
    auto peek_is = [&](char want) {
      if (pos_ < text_.size() && text_[pos_] == want) {
        ++pos_;
        return true;
      }
      return false;
    };
    switch (c) {
      case '(': return make(TokenKind::LParen, begin);
      case ')': return make(TokenKind::RParen, begin);
      case ';': return make(TokenKind::Semicolon, begin);
      case '.': return make(TokenKind::Dot, begin);
      case ',': return make(TokenKind::Comma, begin);
      case ':': return make(TokenKind::Colon, begin);
      case '[': return make(TokenKind::LBracket, begin);
      case ']': return make(TokenKind::RBracket, begin);
      case '+': return make(TokenKind::Plus, begin);
      case '-': return make(TokenKind::Minus, begin);
      case '*': return make(TokenKind::Star, begin);
      case '/': return make(TokenKind::Slash, begin);
      case '%': return make(TokenKind::Percent, begin);
      case '<':
        if (peek_is('>')) return invalid(begin, "'<>' is not an operator; inequality is '!='");
        return make(peek_is('=') ? TokenKind::LessEqual : TokenKind::Less, begin);
      case '>': return make(peek_is('=') ? TokenKind::GreaterEqual : TokenKind::Greater, begin);
      case '=':
        if (peek_is('=')) return invalid(begin, "'==' is not an operator; equality is '='");
        return make(TokenKind::Equal, begin);
      case '!':
        if (peek_is('=')) return make(TokenKind::NotEqual, begin);
        return invalid(begin, "'!' is not an operator; use 'not' or '!='");
      default: break;
    }
    // Consume a whole UTF-8 sequence so that the caret covers one character.
    while (pos_ < text_.size() && (static_cast<unsigned char>(text_[pos_]) & 0xC0) == 0x80) ++pos_;
    // Comparisons typed as one mathematical sign (U+2265, U+2264, U+2260): say the ASCII spelling.
    const std::string_view sign = text_.substr(begin, pos_ - begin);
    if (sign == "\u2265") return invalid(begin, "'\u2265' is not an operator; use '>='");
    if (sign == "\u2264") return invalid(begin, "'\u2264' is not an operator; use '<='");
    if (sign == "\u2260") return invalid(begin, "'\u2260' is not an operator; use '!='");
    const unsigned char u = static_cast<unsigned char>(c);
    std::string shown = (u >= 0x20 && u < 0x7f) ? "'" + std::string(1, c) + "'"
                                                : "byte 0x" + std::string(1, "0123456789abcdef"[u >> 4]) +
                                                      std::string(1, "0123456789abcdef"[u & 15]);
    return invalid(begin, "unexpected character " + shown);
  }

  std::string_view text_;
  size_t pos_ = 0;
  size_t base_ = 0;  // where the text starts in the file its spans count in
};

bool is_keyword(TokenKind k) { return k >= TokenKind::Modules && k <= TokenKind::Component; }

bool is_reserved(TokenKind k) { return k >= TokenKind::Modules && k <= TokenKind::Next; }

bool is_comparison(TokenKind k) { return k >= TokenKind::Less && k <= TokenKind::LessEqual; }

std::string describe(TokenKind k) {
  switch (k) {
    case TokenKind::Name: return "a name";
    case TokenKind::Integer: return "a number";
    case TokenKind::NonInteger: return "a non-integer number";
    case TokenKind::Modules: return "'modules'";
    case TokenKind::Not: return "'not'";
    case TokenKind::And: return "'and'";
    case TokenKind::Or: return "'or'";
    case TokenKind::Neighbor: return "'neighbor'";
    case TokenKind::Last: return "'last'";
    case TokenKind::Next: return "'next'";
    case TokenKind::In: return "'in'";
    case TokenKind::Neighbors: return "'neighbors'";
    case TokenKind::Count: return "'count'";
    case TokenKind::Sum: return "'sum'";
    case TokenKind::Min: return "'min'";
    case TokenKind::Max: return "'max'";
    case TokenKind::Abs: return "'abs'";
    case TokenKind::Then: return "'then'";
    case TokenKind::Set: return "'set'";
    case TokenKind::Remove: return "'remove'";
    case TokenKind::Once: return "'once'";
    case TokenKind::Historically: return "'historically'";
    case TokenKind::Since: return "'since'";
    case TokenKind::Times: return "'times'";
    case TokenKind::Id: return "'id'";
    case TokenKind::Within: return "'within'";
    case TokenKind::All: return "'all'";
    case TokenKind::Argmin: return "'argmin'";
    case TokenKind::Argmax: return "'argmax'";
    case TokenKind::Component: return "'component'";
    case TokenKind::LParen: return "'('";
    case TokenKind::RParen: return "')'";
    case TokenKind::Semicolon: return "';'";
    case TokenKind::Dot: return "'.'";
    case TokenKind::Comma: return "','";
    case TokenKind::Colon: return "':'";
    case TokenKind::LBracket: return "'['";
    case TokenKind::RBracket: return "']'";
    case TokenKind::Plus: return "'+'";
    case TokenKind::Minus: return "'-'";
    case TokenKind::Star: return "'*'";
    case TokenKind::Slash: return "'/'";
    case TokenKind::Percent: return "'%'";
    case TokenKind::Less: return "'<'";
    case TokenKind::Greater: return "'>'";
    case TokenKind::Equal: return "'='";
    case TokenKind::NotEqual: return "'!='";
    case TokenKind::GreaterEqual: return "'>='";
    case TokenKind::LessEqual: return "'<='";
    case TokenKind::Invalid: return "an invalid character";
    case TokenKind::End: return "end of input";
  }
  return "?";
}

TokenStream::TokenStream(const SourceText& source) : lexer_(std::make_unique<Lexer>(source)) {}
TokenStream::~TokenStream() = default;
Token TokenStream::next() { return lexer_->token(); }

std::vector<Token> lex(const SourceText& source) {
  TokenStream stream(source);
  std::vector<Token> out;
  for (;;) {
    out.push_back(stream.next());
    if (out.back().kind == TokenKind::End) return out;
  }
}

}  // namespace dw::watch
