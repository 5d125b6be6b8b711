// Prints what instrumentation costs and how close static counts come to measured ones:
//   - CPU: instrument_shader() time against the driver's own compile and link of the program;
//   - GPU (llvmpipe here): frame time of the instrumented program / the plain program;
//   - static instructions of the fragment shader against the measured per-invocation average.
// Usage: instrument_bench [size=512] [frames=40]
#include "egl_context.hpp"
#include "gl_program.hpp"
#include "glbudget/instrument/instrument.hpp"
#include "program_cases.hpp"
#include "shader_files.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace glbudget::instrument;
using namespace glbudget::test;
using Clock = std::chrono::steady_clock;

namespace {

double milliseconds(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

template <typename F>
double median_ms(int repetitions, F&& f) {
  std::vector<double> times;
  for (int i = 0; i < repetitions; ++i) {
    const auto start = Clock::now();
    f();
    times.push_back(milliseconds(Clock::now() - start));
  }
  return median(times);
}

GLuint program_from(const std::string& vertex, const std::string& fragment) {
  const CompiledShader vs = compile_shader(GL_VERTEX_SHADER, vertex), fs = compile_shader(GL_FRAGMENT_SHADER, fragment);
  const LinkedProgram p = link_program({vs.id, fs.id});
  glDeleteShader(vs.id);
  glDeleteShader(fs.id);
  if (!p.ok) {
    std::fprintf(stderr, "link failed: %s%s%s\n", vs.log.c_str(), fs.log.c_str(), p.log.c_str());
    std::exit(1);
  }
  return p.id;
}

void run(const ProgramCase& c, int size, int frames) {
  EglContext context(c.profile);
  if (!context.ok()) {
    std::fprintf(stderr, "%s\n", context.error().c_str());
    std::exit(1);
  }
  QuadTarget target(size);
  GLint bindings = 0;
  glGetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &bindings);
  const int binding = bindings - 1;

  const std::string vertex = shader_file(c.vertex_file), fragment = shader_file(c.fragment_file);
  InstrumentResult vi, fi;
  const double instrument_ms = median_ms(20, [&] {
    vi = instrument_shader({{vertex}, Stage::vertex, binding});
    fi = instrument_shader({{fragment}, Stage::fragment, binding});
  });
  const double build_ms = median_ms(20, [&] { glDeleteProgram(program_from(vertex, fragment)); });

  const GLuint plain = program_from(vertex, fragment);
  const GLuint counted = program_from(vi.instrumented_source, fi.instrumented_source);
  glShaderStorageBlockBinding(counted, glGetProgramResourceIndex(counted, GL_SHADER_STORAGE_BLOCK, kCounterBlockName),
                              static_cast<GLuint>(binding));
  c.set_uniforms(plain);
  c.set_uniforms(counted);
  GLuint counters = 0;
  glCreateBuffers(1, &counters);
  const CounterWords zero{};
  glNamedBufferData(counters, kCounterBytes, zero.data(), GL_DYNAMIC_READ);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, static_cast<GLuint>(binding), counters);

  auto frame = [&](GLuint program) {
    return [&target, program] {
      target.draw_without_readback(program);
      glFinish();
    };
  };
  for (int i = 0; i < 3; ++i) {  // warm up: first draws compile the variant
    frame(plain)();
    frame(counted)();
  }
  std::vector<double> plain_ms, counted_ms;
  for (int round = 0; round < 4; ++round) {  // interleaved, so drift hits both alike
    plain_ms.push_back(median_ms(frames / 4, frame(plain)));
    counted_ms.push_back(median_ms(frames / 4, frame(counted)));
  }
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  CounterWords words{};
  glGetNamedBufferSubData(counters, 0, kCounterBytes, words.data());
  const StageAverages fs = averages(read_stage_counts(words, Stage::fragment));

  const double plain_frame = median(plain_ms), counted_frame = median(counted_ms);
  std::printf(
      "%-8s %5d² | instrument %6.2f ms, driver build %6.2f ms, ratio %5.2f | frame plain %8.3f ms, "
      "instrumented %8.3f ms, ratio %5.2f | fs static ins %3llu, measured ins/inv %7.2f, tex/inv %5.2f\n",
      c.name, size, instrument_ms, build_ms, instrument_ms / build_ms, plain_frame, counted_frame,
      counted_frame / plain_frame, static_cast<unsigned long long>(fi.figures->instructions),
      fs.instructions_per_invocation.value_or(0.0), fs.texel_accesses_per_invocation.value_or(0.0));
  glDeleteBuffers(1, &counters);
  glDeleteProgram(plain);
  glDeleteProgram(counted);
}

}  // namespace

int main(int argc, char** argv) {
  setenv("MESA_SHADER_CACHE_DISABLE", "true", 1);  // time real compiles
  const int size = argc > 1 ? std::max(16, std::atoi(argv[1])) : 512;
  const int frames = argc > 2 ? std::max(4, std::atoi(argv[2])) : 40;
  for (const ProgramCase& c : program_cases()) run(c, size, frames);
}
