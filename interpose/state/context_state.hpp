// Per-context and per-share-group state. Shaders and programs are shared between contexts
// of a share group; query objects and program pipelines are not, so they live per context.
#pragma once
#include <array>
#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "configuration.hpp"
#include "frame_row.hpp"
#include "glbudget/instrument/instrument.hpp"
#include "variants.hpp"
#include "pass_counter.hpp"
#include "stable_hash.hpp"

namespace glbudget {

class Instrumentation;

struct ShaderInfo {
  GLenum stage = 0;
  std::string source;  // the strings the app passed, concatenated
  // Instrumentation (shader_instrumentation.hpp): the driver holds the instrumented source in
  // place of the app's until the app sets a new one; the compiled code is instrumented until
  // the next compile.
  bool driver_source_instrumented = false;
  bool compiled_instrumented = false;
  bool binding_in_source = true;                     // else the link sets the counter block's binding
  std::optional<instrument::StaticFigures> figures;  // when glslang parsed it
};

struct ProgramInfo {
  std::vector<GLuint> shaders;  // attached now
  PassId pass = 0;              // from the sources at the last link
  bool linked = false;
  bool instrumented = false;             // linked from instrumented shaders: its draws need the counters
  int manifest_pass = -1;                // the manifest pass that matched it at the last link
  std::shared_ptr<VariantSet> variants;  // its variant programs (apply/variants.hpp), if any
  // The app deleted it while a variant stood in for it in the driver: deleted for real when
  // the app stops using it (the driver would have deleted it at once, not being in use).
  bool delete_pending = false;
  // Locations the app bound by name before linking, also for names the program lacks (an
  // engine binding one scheme for every program): replayed on each variant.
  std::vector<std::pair<std::string, GLuint>> attribute_bindings;
  std::vector<std::pair<std::string, std::pair<GLuint, GLuint>>> frag_data_bindings;  // colour, index
  // Why its fragment shader could not be rewritten to see the app's pixels ("": it was, or
  // needed not be): said once it draws into a scaled target.
  std::string app_space_refused;
};

class TargetScaler;
class ProbeFrames;

struct ShareGroup {
  std::mutex mu;
  std::unordered_map<GLuint, ShaderInfo> shaders;
  std::unordered_map<GLuint, ProgramInfo> programs;
  std::atomic<bool> has_variants{false};  // any program of the group has variants
  std::atomic<bool> has_refused{false};   // any has app_space_refused
  // Any matched a manifest pass: a pass of scale levels alone has no variants, yet its draws
  // must be known as its own for the targets it scales ("self", "pass:NAME").
  std::atomic<bool> has_matched{false};
};

struct ContextState {
  void* handle = nullptr;   // GLXContext or EGLContext
  void* display = nullptr;  // its Display* / EGLDisplay
  bool egl = false;         // made current through EGL (else GLX)
  int index = 0;            // log name: order of first make-current in the process
  std::shared_ptr<ShareGroup> group;
  bool bound = false;        // current on some thread (guarded by the registry lock)
  bool initialized = false;  // caps detected and counter built (first make-current)
  GlCaps caps;
  std::unique_ptr<PassCounter> counter;
  std::unique_ptr<Instrumentation> instrumentation;  // GLBUDGET_INSTRUMENT, made on first use
  bool instrumentation_probed = false;
  std::optional<std::vector<std::string>> extensions;  // the driver's, once read (state/gl_programs.cpp)

  GLuint program = 0;       // the app's program (the driver may have a variant of it bound)
  GLuint real_program = 0;  // the program the driver has bound
  GLuint pipeline = 0;
  std::shared_ptr<const VariantSet> bound_variants;  // of `program`, when it has variants
  int manifest_pass = -1;                            // the manifest pass of `program`
  bool app_space_refused = false;                    // `program` has ProgramInfo::app_space_refused
  // The app's subroutine selections per stage slot while `program` has variants, in its terms
  // (apply/subroutines.hpp): re-applied after glbudget's own glUseProgram.
  std::array<SubroutineSelection, kShaderStages> subroutines;
  Levels config;                          // the configuration this context draws (changes only at its swap)
  std::unique_ptr<TargetScaler> targets;  // render-target scaling (apply/render_targets.hpp)
  std::unique_ptr<ProbeFrames> probes;    // quality probes in lockstep (apply/probes.hpp)
  std::unordered_map<GLuint, std::array<GLuint, 6>> pipeline_stages;  // the app's, per context
  // What the driver holds in each pipeline's stages (a variant where the configuration says).
  std::unordered_map<GLuint, std::array<GLuint, 6>> pipeline_real_stages;
  std::unordered_map<GLuint, GLuint> pipeline_active;  // glActiveShaderProgram, the app's
  // With a pipeline bound and no program, non-DSA glUniform* go to its active program.
  std::shared_ptr<const VariantSet> pipeline_uniform_variants;
  // With a pipeline bound and no program: the variants of its fragment stage's program, whose
  // copy in app coordinates gets its ratios before each draw (apply/app_space_uniforms.hpp).
  std::shared_ptr<const VariantSet> pipeline_fragment_variants;
  bool list_compile_only = false;
  // Errors the app had not read when the shim's own GL work began (state/gl_errors.hpp):
  // its glGetError answers these first.
  std::vector<GLenum> app_errors;

  uint64_t frame = 0;
  int64_t next_deadline_ns = 0;  // GLBUDGET_FPS pacing
};

// The context current on this thread (null if none, or not yet initialised).
extern thread_local ContextState* t_ctx __attribute__((tls_model("initial-exec")));
inline ContextState* current_context() { return t_ctx; }

// Context life cycle, called by the GLX and EGL hooks after the real call succeeded.
void context_created(void* handle, void* display, void* share_with);
void context_will_change(void* handle);                            // before the real make-current
void context_made_current(void* handle, void* display, bool egl);  // handle null: released
void context_destroyed(void* handle);
void display_terminated(void* display);

// Takes the configuration for the context's next frame (at its swap, and when it starts).
void apply_configuration(ContextState& c, const Levels& config);

// Whether the context builds copies of the app's programs: variants for a manifest's passes,
// or its programs in app coordinates while render targets may be scaled (apply/variants.hpp).
bool shadows_programs(const ContextState& c);

// Binds, in the driver, the variant of the app's current program that the context's
// configuration draws with (or the app's own program).
void bind_program(ContextState& c);
// Puts in each pipeline's stages the variants the configuration asks for.
void bind_pipeline_stages(ContextState& c);

// Re-derives the pass of the current binding (program, pipeline or fixed function).
void update_pass(ContextState& c);
// Whether a stage of the bound program pipeline is held by a variant whose level skips the
// pass's draws under c.config.
bool pipeline_skips(ContextState& c);
PassId pass_of_program(ShareGroup& g, GLuint program);  // caller holds g.mu

// Every known context, for the final flush at exit.
void for_each_context(void (*fn)(ContextState&));

}  // namespace glbudget
