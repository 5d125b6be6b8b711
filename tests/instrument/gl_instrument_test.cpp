// The instrumenter in a real context (Mesa via EGL surfaceless): the instrumented programs
// compile and link, count exactly the hand-counted operations and texel accesses per
// invocation, keep the app's interface tables, line numbers and rendered image.
#include "egl_context.hpp"
#include "gl_program.hpp"
#include "glbudget/instrument/instrument.hpp"
#include "program_cases.hpp"
#include "shader_files.hpp"

#include <catch2/catch.hpp>

#include <cstdlib>

using namespace glbudget::instrument;
using namespace glbudget::test;

namespace {

struct Built {
  CompiledShader vertex, fragment;
  LinkedProgram program;
};

Built build(const std::string& vertex_source, const std::string& fragment_source) {
  Built b;
  b.vertex = compile_shader(GL_VERTEX_SHADER, vertex_source);
  b.fragment = compile_shader(GL_FRAGMENT_SHADER, fragment_source);
  b.program = link_program({b.vertex.id, b.fragment.id});
  return b;
}

GLuint counter_binding() {
  GLint bindings = 0;
  glGetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &bindings);
  return static_cast<GLuint>(bindings - 1);  // the highest: apps fill bindings from 0
}

CounterWords read_counters(GLuint buffer) {
  CounterWords words{};
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glGetNamedBufferSubData(buffer, 0, kCounterBytes, words.data());
  return words;
}

void run_case(const ProgramCase& c) {
  // Mesa skips compiling shaders its disk cache has seen linked, and then logs no
  // warnings; the line-number checks need a real compile.
  setenv("MESA_SHADER_CACHE_DISABLE", "true", 1);
  EglContext context(c.profile);
  REQUIRE(context.ok());
  QuadTarget target;
  const GLuint binding = counter_binding();

  const std::string vertex_source = shader_file(c.vertex_file), fragment_source = shader_file(c.fragment_file);
  const InstrumentResult vertex = instrument_shader({{vertex_source}, Stage::vertex, static_cast<int>(binding)});
  const InstrumentResult fragment = instrument_shader({{fragment_source}, Stage::fragment, static_cast<int>(binding)});
  INFO(vertex.error << fragment.error);
  REQUIRE(vertex.ok);
  REQUIRE(fragment.ok);

  const Built original = build(vertex_source, fragment_source);
  const Built instrumented = build(vertex.instrumented_source, fragment.instrumented_source);
  INFO(instrumented.vertex.log << instrumented.fragment.log << instrumented.program.log);
  REQUIRE(original.program.ok);
  REQUIRE(instrumented.vertex.ok);
  REQUIRE(instrumented.fragment.ok);
  REQUIRE(instrumented.program.ok);
  if (!fragment.binding_in_source) {
    const GLuint block = glGetProgramResourceIndex(instrumented.program.id, GL_SHADER_STORAGE_BLOCK, kCounterBlockName);
    REQUIRE(block != GL_INVALID_INDEX);
    glShaderStorageBlockBinding(instrumented.program.id, block, binding);
  }

  // The driver names the same lines in its messages.
  INFO("original fragment log: " << original.fragment.log);
  CHECK(logged_lines(original.fragment.log) == c.fragment_warning_lines);
  CHECK(logged_lines(instrumented.vertex.log) == logged_lines(original.vertex.log));
  CHECK(logged_lines(instrumented.fragment.log) == logged_lines(original.fragment.log));
  // The app sees the same uniforms, blocks, inputs and outputs.
  CHECK(interface_table(instrumented.program.id, "glbudget_") == interface_table(original.program.id, "glbudget_"));

  // Start the fragment instruction counter just below 2^32 to exercise the carry.
  CounterWords initial{};
  const std::uint32_t near_wrap = 0xFFFFFFF0u;
  initial[word_index(Stage::fragment, Quantity::instructions)] = near_wrap;
  GLuint counters = 0;
  glCreateBuffers(1, &counters);
  glNamedBufferData(counters, kCounterBytes, initial.data(), GL_DYNAMIC_READ);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, counters);

  c.set_uniforms(original.program.id);
  c.set_uniforms(instrumented.program.id);
  const auto expected_image = target.draw(original.program.id);
  const auto image = target.draw(instrumented.program.id);
  CHECK(image == expected_image);
  CHECK(glGetError() == GL_NO_ERROR);

  const CounterWords words = read_counters(counters);
  StageCounts fragment_counts = read_stage_counts(words, Stage::fragment);
  REQUIRE(fragment_counts.instructions > 0xFFFFFFFFull);  // carried into the high word
  fragment_counts.instructions -= near_wrap;
  const StageAverages fs = averages(fragment_counts);
  const StageAverages vs = averages(read_stage_counts(words, Stage::vertex));

  CHECK(fs.invocations == QuadTarget::kSize * QuadTarget::kSize);
  CHECK(*fs.instructions_per_invocation == c.fragment_instructions);
  CHECK(*fs.texel_accesses_per_invocation == c.fragment_texels);
  CHECK(vs.invocations >= 4);
  CHECK(*vs.instructions_per_invocation == 5.0);
  CHECK(*vs.texel_accesses_per_invocation == 0.0);
  glDeleteBuffers(1, &counters);
}

}  // namespace

TEST_CASE("GLSL 3.30 core: uniform loop, texture in a called function, half-taken branch", "[gl]") {
  run_case(program_case("loops"));
}

TEST_CASE("GLSL ES 3.00: discard, early return, break, continue, while, do, switch", "[gl]") {
  run_case(program_case("jumps"));
}

TEST_CASE("GLSL 1.20 compatibility: texture2D, macros, #line, a driver warning", "[gl]") {
  run_case(program_case("compat"));
}
