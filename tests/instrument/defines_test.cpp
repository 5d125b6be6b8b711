// set_defines: a manifest level's #defines, redefined in place or added after the header.
#include <catch2/catch.hpp>

#include "glbudget/instrument/defines.hpp"

using glbudget::instrument::set_defines;

TEST_CASE("an existing object-like #define is redefined in place, byte for byte as the app writes it") {
  const std::string app = "#version 330 core\n#define SHADING_MODEL 2\nvoid main() {}\n";
  CHECK(set_defines(app, {{"SHADING_MODEL", "1"}}) == "#version 330 core\n#define SHADING_MODEL 1\nvoid main() {}\n");
  // Spacing and a trailing comment on the app's line do not stop the match.
  CHECK(set_defines("#version 330\n  #  define  N 4 // samples\nx\n", {{"N", "8"}}) ==
        "#version 330\n#define N 8\nx\n");
}

TEST_CASE("names are matched whole; function-like macros and other directives are left alone") {
  const std::string app = "#version 330\n#define SAMPLES_MAX 4\n#define SAMPLES(x) x\n#ifdef SAMPLES\n#endif\n";
  const std::string out = set_defines(app, {{"SAMPLES", "9"}});
  CHECK(out.find("#define SAMPLES_MAX 4\n") != std::string::npos);
  CHECK(out.find("#define SAMPLES(x) x\n") != std::string::npos);
  // Not defined as an object-like macro: added after #version.
  CHECK(out.rfind("#version 330\n#define SAMPLES 9\n#line 2\n", 0) == 0);
}

TEST_CASE("a new macro goes after #version and the #extension lines, and a #line keeps the app's numbers") {
  const std::string app =
      "#version 310 es\n// comment\n#extension GL_EXT_a : enable\n\n#extension GL_EXT_b : require\nprecision highp "
      "float;\n";
  const std::string out = set_defines(app, {{"A", "1"}, {"B", "2.0"}});
  CHECK(out ==
        "#version 310 es\n// comment\n#extension GL_EXT_a : enable\n\n#extension GL_EXT_b : require\n"
        "#define A 1\n#define B 2.0\n#line 6\nprecision highp float;\n");
}

TEST_CASE("#line follows the GLSL version's rule: before 3.30 the next line is L + 1") {
  CHECK(set_defines("#version 120\nvoid main(){}\n", {{"Q", "1"}}) ==
        "#version 120\n#define Q 1\n#line 1\nvoid main(){}\n");
  CHECK(set_defines("#version 330\nvoid main(){}\n", {{"Q", "1"}}) ==
        "#version 330\n#define Q 1\n#line 2\nvoid main(){}\n");
  // No #version: GLSL 1.10, macros go first.
  CHECK(set_defines("void main(){}", {{"Q", "1"}}) == "#define Q 1\n#line 0\nvoid main(){}");
}

TEST_CASE("a continued #define keeps its physical line count; CRLF and a missing final newline survive") {
  const std::string app = "#version 330\n#define LONG 1 + \\\n 2\nint x = LONG;";
  CHECK(set_defines(app, {{"LONG", "3"}}) == "#version 330\n#define LONG 3\n\nint x = LONG;");
  CHECK(set_defines("#version 330\r\n#define K 1\r\n", {{"K", "2"}}) == "#version 330\r\n#define K 2\n");
  CHECK(set_defines("#version 330", {{"K", "2"}}) == "#version 330\n#define K 2\n#line 2\n");
}

TEST_CASE("no defines: the source is returned unchanged; every occurrence is redefined") {
  CHECK(set_defines("abc", {}) == "abc");
  const std::string app = "#version 330\n#define K 1\n#undef K\n#define K 5\n";
  CHECK(set_defines(app, {{"K", "7"}}) == "#version 330\n#define K 7\n#undef K\n#define K 7\n");
}
