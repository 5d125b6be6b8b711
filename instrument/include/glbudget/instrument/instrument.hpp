// glbudget shader instrumentation: GLSL in, GLSL out, no GL.
//
// instrument_shader() parses a shader with glslang and rewrites its (preprocessed) source so
// that every invocation counts the operations it executes and the texels it fetches, and adds
// its totals to a shader storage block when it ends. The app's uniforms, inputs, outputs and
// blocks keep their names, types and layout qualifiers, and its line numbers are kept (the
// declarations glbudget adds are followed by a #line directive).
//
// Counting rule (what "an operation" is)
//   The unit is a node of glslang's AST after glslang's own constant folding:
//   - every unary and binary operator node counts 1 (arithmetic, logic, comparison, bitwise,
//     assignment and compound assignment, ++/--, implicit or explicit conversions, dynamic
//     indexing), except the free addressing nodes: constant index `a[2]`, struct member
//     `s.m`, swizzle `v.xy`, and the comma operator;
//   - every built-in function call and every constructor that survives folding counts 1;
//   - every call of a user function counts 1 at the call site; the callee's body is counted
//     each time it runs;
//   - `?:` counts 1; `&&`, `||` count 1; their operands are all counted (they do not branch:
//     GPU compilers flatten them);
//   - control-flow statements (if, loops, switch, return, break, continue, discard) count 0;
//     the operators in their conditions count as above, a loop condition each time it is
//     evaluated (iterations + 1 for a loop that exits through its condition), a for-loop
//     increment each time it runs.
//   A block (a straight-line run of statements, a loop condition, a loop increment) is
//   counted in full when it is entered; a discard inside a called function therefore still
//   counts the rest of the caller's block.
// Texel access rule: every sampling built-in (texture*, texelFetch*, textureGather*, sparse
//   and footprint variants; glslang's isSampling()) counts 1 texel access per call, whatever
//   the number of texels the hardware reads. Size/LOD/level queries count 0.
// Invocation rule: an invocation is counted when main returns, ends or discards.
//   Helper invocations do not write memory and are not counted.
//
// Counters: one SSBO block, `glbudget_Counters`, bound at the binding the caller chooses
// (the highest the driver offers, so the app cannot be using it). It holds
// kCounterWords 32-bit words; each (stage, quantity) pair is a 64-bit value split into a low
// and a high word (word_index()), accumulated with 32-bit atomics and an explicit carry, so
// it works on every GLSL that has SSBOs and does not overflow on long runs. All stages of a
// program declare the same block and write disjoint words. Zero the buffer before use.
//
// Use from the shim (GL side, not in this library):
//   glCompileShader: r = instrument_shader({app strings, stage, binding, driver extensions});
//     if r.ok, compile r.instrumented_source in a shadow shader beside the app's; otherwise
//     (or if the shadow fails to compile or link) print one `glbudget:` line with r.error
//     and keep the app's shader.
//   glLinkProgram: link the shadow shaders; if !r.binding_in_source, call
//     glShaderStorageBlockBinding(shadow, index of kCounterBlockName, binding).
//   draws: bind a zeroed kCounterBytes buffer at `binding` (restore the app's binding after).
//   readback (a few frames late, through a copy and a fence, never stalling):
//     read_stage_counts(words, stage) per stage, add up rounds, averages() → Ins, Tex.
//   GLBUDGET_DUMP: dump.hpp.
// Limits: GLSL ES 1.00 has no storage buffers (static figures only). Preprocessing is
// glslang's: pass driver_extensions so extension conditionals match the driver.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace glbudget::instrument {

enum class Stage { vertex, tess_control, tess_evaluation, geometry, fragment, compute };
inline constexpr int kStageCount = 6;
const char* stage_name(Stage stage);  // "vertex", "fragment", ...

// Counter layout in the SSBO (std430 uint array).
enum class Quantity { instructions, texel_accesses, invocations };
inline constexpr int kQuantityCount = 3;
inline constexpr int kCounterWords = kStageCount * kQuantityCount * 2;
inline constexpr std::size_t kCounterBytes = kCounterWords * sizeof(std::uint32_t);
inline constexpr const char* kCounterBlockName = "glbudget_Counters";
// Index of the low word of (stage, quantity); the high word follows it.
constexpr int word_index(Stage stage, Quantity quantity) {
  return (static_cast<int>(stage) * kQuantityCount + static_cast<int>(quantity)) * 2;
}

// Figures that need no execution.
struct StaticFigures {
  int blocks = 0;                  // counted blocks (runs, loop conditions, loop increments)
  std::uint64_t instructions = 0;  // operations over all blocks of all functions, each once
  int texture_calls = 0;           // sampling calls in the source
};

struct InstrumentRequest {
  InstrumentRequest() = default;
  InstrumentRequest(std::vector<std::string> sources_, Stage stage_, int ssbo_binding_,
                    std::optional<std::vector<std::string>> driver_extensions_ = std::nullopt)
      : sources(std::move(sources_)),
        stage(stage_),
        ssbo_binding(ssbo_binding_),
        driver_extensions(std::move(driver_extensions_)) {}

  std::vector<std::string> sources;  // the strings the app passed to glShaderSource
  Stage stage = Stage::fragment;
  int ssbo_binding = 0;  // binding point of the counter block
  // The driver's extensions (glGetStringi(GL_EXTENSIONS, i)). When given, `#if`/`#ifdef`
  // on extension macros follow the driver, as in the app's own shader; when absent they
  // follow glslang's list of extensions, which may differ.
  std::optional<std::vector<std::string>> driver_extensions;
};

struct InstrumentResult {
  bool ok = false;
  std::string error;                // why instrumentation failed (one line), when !ok
  std::string instrumented_source;  // one string (GL concatenates the app's strings too)
  // True when the source carries `layout(binding = ssbo_binding)`. When false (GLSL
  // without binding qualifiers) the caller must set the binding with
  // glShaderStorageBlockBinding on kCounterBlockName after linking.
  bool binding_in_source = false;
  std::optional<StaticFigures> figures;  // present whenever glslang could parse the shader
};

InstrumentResult instrument_shader(const InstrumentRequest& request);

// Per-stage totals read back from the SSBO and their per-invocation averages.
struct StageCounts {
  std::uint64_t instructions = 0;
  std::uint64_t texel_accesses = 0;
  std::uint64_t invocations = 0;
};
struct StageAverages {
  std::uint64_t invocations = 0;
  // Empty when no invocation was counted.
  std::optional<double> instructions_per_invocation;
  std::optional<double> texel_accesses_per_invocation;
};

using CounterWords = std::array<std::uint32_t, kCounterWords>;
StageCounts read_stage_counts(const CounterWords& words, Stage stage);
StageAverages averages(const StageCounts& counts);
// Sum of two readbacks (counters are read and reset in several rounds).
StageCounts operator+(const StageCounts& a, const StageCounts& b);

}  // namespace glbudget::instrument
