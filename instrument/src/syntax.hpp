// Statement structure of preprocessed GLSL, found from tokens alone. glslang's AST does not
// record where statements begin and end in the text, which a source rewrite needs; this
// small parser recovers exactly that (function bodies, statements, control-flow headers)
// and nothing more. Operator counts come from the AST (ast_census) and are attached to these
// text ranges by position.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace glbudget::instrument::syntax {

struct Range {
  std::size_t begin = 0;  // byte offsets into the text, [begin, end)
  std::size_t end = 0;
  bool empty() const { return begin >= end; }
};

struct Statement;
using StatementList = std::vector<std::unique_ptr<Statement>>;

struct Statement {
  enum class Kind {
    simple,    // expression or declaration statement, `;` included
    empty,     // a lone `;`
    compound,  // { ... }
    if_,       // if (head) body [else else_body]
    for_,      // for (init; head; step) body
    while_,    // while (head) body
    do_while,  // do body while (head);
    switch_,   // switch (head) { children with labels }
    label,     // case ...: / default:
    return_,   // return [expr];
    discard,
    break_,
    continue_
  };
  Kind kind = Kind::simple;
  Range whole;                           // the full statement text
  Range head;                            // condition / switch selector / for condition / return expression
  Range init;                            // for-init (its `;` excluded)
  Range step;                            // for-increment
  std::unique_ptr<Statement> body;       // if, for, while, do
  std::unique_ptr<Statement> else_body;  // if
  StatementList children;                // compound, switch (its braces are `whole`)
};

struct Function {
  std::string name;
  Range whole;                      // from the return type to the closing brace
  std::unique_ptr<Statement> body;  // compound
};

struct Directive {
  Range whole;       // `#...` up to (not including) the newline
  std::string name;  // "version", "extension", "line", ...
};

struct Unit {
  std::vector<Function> functions;
  std::vector<Directive> directives;
};

// Parses preprocessed GLSL (no macros, no conditionals). Throws std::runtime_error with a
// one-line reason on text it does not understand.
Unit parse(std::string_view text);

}  // namespace glbudget::instrument::syntax
