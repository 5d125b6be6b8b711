// Shader instrumentation in the shim (GLBUDGET_INSTRUMENT, GLBUDGET_DUMP): the GL side of
// instrument/. On glCompileShader the app's source is rewritten to count what each invocation
// executes; the driver compiles the instrumented source in the app's own shader object (the
// rewrite keeps every name and location, so the app sees the same program), and falls back
// to the app's source, with one `glbudget:` line, if anything fails. glGetShaderSource keeps
// answering with the app's source. Draws of instrumented programs write counters into a
// buffer at the highest shader-storage binding, read back a few frames late.
// glGetProgramBinary of an instrumented program returns an empty binary (never cache ours).
// Limits: compute shaders (dispatches are not bound to counters) and glCreateShaderProgramv
// programs (no compile step to hook) are not instrumented; GLSL ES 1.00 has no storage
// buffers. The app must leave the highest shader-storage binding unused.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "context_state.hpp"
#include "counter_buffers.hpp"
#include "glbudget/instrument/dump.hpp"
#include "hooks_generated.hpp"

namespace glbudget {

// Per context: what the driver offers, and the counter buffers.
class Instrumentation {
 public:
  Instrumentation(int binding, std::vector<std::string> extensions)
      : binding_(binding), extensions_(std::move(extensions)), buffers_(binding) {}
  int binding() const { return binding_; }
  const std::vector<std::string>& extensions() const { return extensions_; }
  CounterBuffers& buffers() { return buffers_; }

 private:
  int binding_;
  std::vector<std::string> extensions_;
  CounterBuffers buffers_;
};

// The context's instrumentation, made on first use; null when it is off or the context has
// no shader storage buffers.
Instrumentation* instrumentation_of(ContextState& c);

// Called by handle_glLinkProgram under the share group's lock, after the real link: sets the
// counter binding, or relinks from the app's sources if the instrumented link failed.
void after_link(ContextState& c, ShareGroup& g, GLuint program, ProgramInfo& info, pfn_glLinkProgram real);

// A variant program (apply/variants.hpp) instrumented like the app's shaders, so that
// `glbudget calibrate --app` measures each level's costs: per stage the source to compile
// (the instrumented one where the rewrite succeeds, else the given one).
struct InstrumentedVariant {
  std::vector<std::string> sources;
  bool any = false;            // some stage is instrumented
  bool needs_binding = false;  // the counter block's binding is set after linking
  instrument::ProgramDump dump;
};
InstrumentedVariant instrument_variant(Instrumentation& inst, const std::vector<std::pair<GLenum, std::string>>& stages,
                                       const std::string& program_hash);
// After the variant linked from those sources: sets its counter binding and lists it in the dump.
void after_variant_link(Instrumentation& inst, GLuint program, const InstrumentedVariant& variant);

// After the bound program or pipeline changed: binds its counters if it is instrumented.
void bind_counters(ContextState& c);

// At each swap (never waits), and when the context stops being current on this thread or the
// process exits (waits: the context is going away).
void instrumentation_swap(ContextState& c);
void instrumentation_release(ContextState& c);

}  // namespace glbudget
