#include "syntax.hpp"

#include <cctype>
#include <stdexcept>

namespace glbudget::instrument::syntax {

namespace {

struct Token {
  std::string_view text;
  std::size_t offset = 0;
  bool is(std::string_view s) const { return text == s; }
  std::size_t end() const { return offset + text.size(); }
};

bool identifier_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

class Lexer {
 public:
  explicit Lexer(std::string_view text) : text_(text) {}

  void run(std::vector<Token>& tokens, std::vector<Directive>& directives) {
    bool line_start = true;
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == '\n') {
        line_start = true;
        ++pos_;
        continue;
      }
      if (std::isspace(static_cast<unsigned char>(c))) {
        ++pos_;
        continue;
      }
      if (c == '/' && peek(1) == '/') {
        skip_until("\n");
        continue;
      }
      if (c == '/' && peek(1) == '*') {
        pos_ += 2;
        skip_until("*/");
        pos_ += 2;
        continue;
      }
      if (c == '#' && line_start) {
        directives.push_back(directive());
        continue;
      }
      line_start = false;
      const std::size_t start = pos_;
      if (identifier_char(c) || (c == '.' && std::isdigit(static_cast<unsigned char>(peek(1))))) {
        const bool number = !std::isalpha(static_cast<unsigned char>(c)) && c != '_';
        while (pos_ < text_.size()) {
          const char d = text_[pos_];
          if (identifier_char(d) || (number && d == '.')) {
            ++pos_;
            continue;
          }
          // exponent sign: 1e-5
          if (number && (d == '+' || d == '-') && (text_[pos_ - 1] == 'e' || text_[pos_ - 1] == 'E') &&
              !(text_[start] == '0' && start + 1 < pos_ && (text_[start + 1] == 'x' || text_[start + 1] == 'X'))) {
            ++pos_;
            continue;
          }
          break;
        }
      } else {
        ++pos_;  // punctuation: single characters are all the structure needs
      }
      tokens.push_back({text_.substr(start, pos_ - start), start});
    }
  }

 private:
  char peek(std::size_t ahead) const { return pos_ + ahead < text_.size() ? text_[pos_ + ahead] : '\0'; }
  void skip_until(std::string_view end) {
    const std::size_t found = text_.find(end, pos_);
    pos_ = found == std::string_view::npos ? text_.size() : found;
  }
  Directive directive() {
    Directive d;
    d.whole.begin = pos_;
    skip_until("\n");
    d.whole.end = pos_;
    std::size_t i = d.whole.begin + 1;
    while (i < pos_ && (text_[i] == ' ' || text_[i] == '\t')) ++i;
    std::size_t j = i;
    while (j < pos_ && identifier_char(text_[j])) ++j;
    d.name = std::string(text_.substr(i, j - i));
    return d;
  }

  std::string_view text_;
  std::size_t pos_ = 0;
};

class Parser {
 public:
  Parser(std::string_view text, std::vector<Token> tokens) : text_(text), tokens_(std::move(tokens)) {}

  std::vector<Function> functions() {
    std::vector<Function> result;
    std::size_t declaration_start = 0;
    while (i_ < tokens_.size()) {
      const Token& t = tokens_[i_];
      if (t.is(";")) {
        declaration_start = ++i_;
        continue;
      }
      if (t.is("{")) {  // struct or interface block body
        i_ = matching(i_) + 1;
        continue;
      }
      if (is_identifier(t) && i_ + 1 < tokens_.size() && tokens_[i_ + 1].is("(")) {
        const std::size_t close = matching(i_ + 1);
        if (close + 1 < tokens_.size() && tokens_[close + 1].is("{")) {
          Function f;
          f.name = std::string(t.text);
          i_ = close + 1;
          f.body = statement();
          f.whole = {tokens_[declaration_start].offset, f.body->whole.end};
          result.push_back(std::move(f));
          declaration_start = i_;
          continue;
        }
        i_ = close + 1;
        continue;
      }
      ++i_;
    }
    return result;
  }

 private:
  static bool is_identifier(const Token& t) {
    return std::isalpha(static_cast<unsigned char>(t.text[0])) || t.text[0] == '_';
  }

  [[noreturn]] void fail(const std::string& what) const {
    std::size_t offset = i_ < tokens_.size() ? tokens_[i_].offset : text_.size();
    std::size_t line = 1;
    for (std::size_t k = 0; k < offset && k < text_.size(); ++k) line += text_[k] == '\n';
    throw std::runtime_error(what + " at preprocessed line " + std::to_string(line));
  }

  const Token& current() const {
    if (i_ >= tokens_.size()) {
      static const Token end_of_text{};
      return end_of_text;
    }
    return tokens_[i_];
  }

  void expect(std::string_view s) {
    if (!current().is(s)) fail("expected '" + std::string(s) + "'");
    ++i_;
  }

  // Index of the bracket closing the one at `open` ((, [ or {); all kinds nest.
  std::size_t matching(std::size_t open) const {
    int depth = 0;
    for (std::size_t k = open; k < tokens_.size(); ++k) {
      const std::string_view s = tokens_[k].text;
      if (s == "(" || s == "[" || s == "{") ++depth;
      if (s == ")" || s == "]" || s == "}") {
        if (--depth == 0) return k;
      }
    }
    throw std::runtime_error("unbalanced brackets");
  }

  // Index of the first `stop` token at bracket depth 0 from the current position.
  std::size_t find_at_depth0(std::string_view stop) const {
    int depth = 0;
    int pending_ternaries = 0;  // a `:` that closes `?` is not a label colon
    for (std::size_t k = i_; k < tokens_.size(); ++k) {
      const std::string_view s = tokens_[k].text;
      if (s == "(" || s == "[" || s == "{") ++depth;
      if (s == ")" || s == "]" || s == "}") --depth;
      if (depth < 0) break;
      if (depth == 0 && s == "?") ++pending_ternaries;
      if (depth == 0 && s == ":" && stop == ":" && pending_ternaries > 0) {
        --pending_ternaries;
        continue;
      }
      if (depth == 0 && s == stop) return k;
    }
    throw std::runtime_error("missing '" + std::string(stop) + "'");
  }

  // Range strictly inside the parentheses starting at the current token; moves past `)`.
  Range parenthesised() {
    if (!current().is("(")) fail("expected '('");
    const std::size_t open = i_, close = matching(open);
    i_ = close + 1;
    return inner(open, close);
  }

  Range inner(std::size_t open, std::size_t close) const {
    if (close == open + 1) return {tokens_[close].offset, tokens_[close].offset};
    return {tokens_[open + 1].offset, tokens_[close - 1].end()};
  }

  std::unique_ptr<Statement> statement() {
    auto s = std::make_unique<Statement>();
    using K = Statement::Kind;
    const Token& t = current();
    if (i_ >= tokens_.size()) fail("unexpected end of text");
    const std::size_t begin = t.offset;
    if (t.is("{")) {
      s->kind = K::compound;
      ++i_;
      while (!current().is("}")) {
        if (i_ >= tokens_.size()) fail("missing '}'");
        s->children.push_back(statement());
      }
      ++i_;
    } else if (t.is(";")) {
      s->kind = K::empty;
      ++i_;
    } else if (t.is("if")) {
      s->kind = K::if_;
      ++i_;
      s->head = parenthesised();
      s->body = statement();
      if (current().is("else")) {
        ++i_;
        s->else_body = statement();
      }
    } else if (t.is("for")) {
      s->kind = K::for_;
      ++i_;
      if (!current().is("(")) fail("expected '('");
      const std::size_t open = i_, close = matching(open);
      ++i_;
      const std::size_t first = find_at_depth0(";");
      i_ = first + 1;
      const std::size_t second = find_at_depth0(";");
      s->init = inner(open, first);
      s->head = inner(first, second);
      s->step = inner(second, close);
      i_ = close + 1;
      s->body = statement();
    } else if (t.is("while")) {
      s->kind = K::while_;
      ++i_;
      s->head = parenthesised();
      s->body = statement();
    } else if (t.is("do")) {
      s->kind = K::do_while;
      ++i_;
      s->body = statement();
      expect("while");
      s->head = parenthesised();
      expect(";");
    } else if (t.is("switch")) {
      s->kind = K::switch_;
      ++i_;
      s->head = parenthesised();
      if (!current().is("{")) fail("expected '{' after switch");
      auto block = statement();
      s->children = std::move(block->children);
    } else if (t.is("case") || t.is("default")) {
      s->kind = K::label;
      i_ = find_at_depth0(":") + 1;
    } else if (t.is("return")) {
      s->kind = K::return_;
      ++i_;
      const std::size_t semicolon = find_at_depth0(";");
      s->head = semicolon == i_ ? Range{tokens_[i_].offset, tokens_[i_].offset}
                                : Range{tokens_[i_].offset, tokens_[semicolon - 1].end()};
      i_ = semicolon + 1;
    } else if (t.is("discard") || t.is("break") || t.is("continue")) {
      s->kind = t.is("discard") ? K::discard : t.is("break") ? K::break_ : K::continue_;
      ++i_;
      expect(";");
    } else {
      s->kind = K::simple;
      i_ = find_at_depth0(";") + 1;
    }
    s->whole = {begin, tokens_[i_ - 1].end()};
    return s;
  }

  std::string_view text_;
  std::vector<Token> tokens_;
  std::size_t i_ = 0;
};

}  // namespace

Unit parse(std::string_view text) {
  Unit unit;
  std::vector<Token> tokens;
  Lexer(text).run(tokens, unit.directives);
  unit.functions = Parser(text, std::move(tokens)).functions();
  return unit;
}

}  // namespace glbudget::instrument::syntax
