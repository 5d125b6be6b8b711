// The context registry: which contexts exist, their share groups, which is current where.
#include <mutex>
#include <unordered_map>

#include "context_state.hpp"
#include "app_signals.hpp"
#include "app_space_uniforms.hpp"
#include "frame_log.hpp"
#include "frame_output.hpp"
#include "gl_calls.hpp"
#include "governing.hpp"
#include "messages.hpp"
#include "options.hpp"
#include "render_targets.hpp"
#include "probes.hpp"
#include "window_size.hpp"
#include "shader_instrumentation.hpp"

namespace glbudget {

thread_local ContextState* t_ctx = nullptr;

namespace {
struct Registry {
  std::mutex mu;
  std::unordered_map<void*, std::unique_ptr<ContextState>> live;
  // Destroyed contexts are kept: GLX lets a destroyed context stay current until released,
  // and another thread may still hold a pointer. They are small.
  std::vector<std::unique_ptr<ContextState>> destroyed;
  int next_index = 0;
};

Registry& registry() {
  static Registry* r = new Registry;  // never destroyed: hooks may run during exit
  return *r;
}

ContextState& find_or_add(Registry& r, void* handle, void* display) {
  auto& slot = r.live[handle];
  if (!slot) {
    slot = std::make_unique<ContextState>();
    slot->handle = handle;
    slot->display = display;
    slot->group = std::make_shared<ShareGroup>();
  }
  return *slot;
}

// A desktop GL context without the queries some columns of the log need: one line each, once
// per process, when frames are logged or governed. GLES contexts never have them (batches
// only, as documented) and say nothing.
void say_what_is_not_measured(const GlCaps& caps) {
  if (caps.gles || caps.major == 0 || !(FrameLog::get().enabled() || governing())) return;
  if (!caps.pipeline_stats)
    say_once("caps:pipeline_statistics",
             "the driver lacks GL_ARB_pipeline_statistics_query: vertices, fragments and primitives are not measured "
             "(empty in the log)");
  if (!caps.timer)
    say_once("caps:timer", "the driver lacks GL_ARB_timer_query: gpu_ns is not measured (empty in the log)");
}

// A context whose render targets cannot all be scaled as the configuration asks: one line
// each, once per process, so that a log's configuration column is never taken for what drew.
void say_what_cannot_scale(const GlCaps& caps, bool blits, bool window_alone) {
  if (blits || caps.major == 0) return;
  const std::string version =
      std::string(caps.gles ? "OpenGL ES " : "OpenGL ") + std::to_string(caps.major) + "." + std::to_string(caps.minor);
  if (!window_alone) {
    say_once("caps:scaling", "this context is " + version +
                                 ", without framebuffer objects and blits (GL 3.0 or GL_ARB_framebuffer_object): "
                                 "nothing is scaled (resolution levels draw at full size)");
    return;
  }
  if (manifest_scales_targets())
    say_once("caps:scaling-targets",
             "this context is " + version +
                 ", without blits: the window's resolution is scaled, the app's own framebuffers "
                 "keep their sizes");
}

void initialise(ContextState& c, Registry& r) {
  if (c.initialized) return;
  if (!load_gl_calls()) return;
  c.initialized = true;
  c.index = r.next_index++;
  c.caps = detect_caps();
  c.counter = std::make_unique<PassCounter>(c.caps);
  // Scaling needs framebuffer objects and blits: GL 3.0, GLES 3.0, or ARB_framebuffer_object in
  // a desktop GL 2.x context. GLES 2.0 has framebuffer objects without blits: there the window
  // alone is scaled, its stand-in drawn.
  const bool blits = TargetScaler::has_blits(c.caps);
  const bool window_alone = c.caps.gles && c.caps.major == 2;
  const bool scales = manifest_scales_targets() || manifest_scales_window();
  if (scales) say_what_cannot_scale(c.caps, blits, window_alone);
  if (scales && (blits || window_alone)) {
    c.targets = std::make_unique<TargetScaler>(c.caps);
    c.counter->set_draw_hook(
        [](void* ctx) {
          auto* cs = static_cast<ContextState*>(ctx);
          cs->targets->on_draw(cs->manifest_pass);
          if (cs->bound_variants)
            give_app_space_for_draw(*cs, *cs->bound_variants);
          else if (cs->pipeline_fragment_variants)
            give_app_space_for_draw(*cs, *cs->pipeline_fragment_variants);
          if (cs->app_space_refused) report_app_space_refused(*cs);
        },
        &c);
  }
  apply_configuration(c, configuration_for_frame(1));
  update_pass(c);
  frame_output_started();
  say_what_is_not_measured(c.caps);
  // After the governor has started: probes are on by default when it governs.
  if (c.targets && probe_settings().period > 0) {
    if (c.targets->blits())
      c.probes = std::make_unique<ProbeFrames>(c);
    else
      say_once("caps:probes",
               "this context has no blits (OpenGL ES 2.0): no quality probes, the governor estimates "
               "errors without them");
  }
}

void retire(Registry& r, void* handle, bool is_current_here) {
  auto it = r.live.find(handle);
  if (it == r.live.end()) return;
  ContextState& c = *it->second;
  if (c.counter) flush_pending_frames(c, is_current_here ? FlushMode::kWait : FlushMode::kCpuOnly);
  r.destroyed.push_back(std::move(it->second));
  r.live.erase(it);
}
}  // namespace

void context_created(void* handle, void* display, void* share_with) {
  if (!handle) return;
  Registry& r = registry();
  std::lock_guard lock(r.mu);
  ContextState& c = find_or_add(r, handle, display);
  if (share_with) {
    auto it = r.live.find(share_with);
    if (it != r.live.end()) c.group = it->second->group;
  }
}

void context_made_current(void* handle, void* display, bool egl) {
  Registry& r = registry();
  std::lock_guard lock(r.mu);
  if (t_ctx) t_ctx->bound = false;
  if (!handle) {
    t_ctx = nullptr;
    t_draw = nullptr;
    t_probe = nullptr;
    return;
  }
  ContextState& c = find_or_add(r, handle, display);
  c.bound = true;
  c.egl = egl;
  initialise(c, r);
  if (c.targets) {
    int w = 0, h = 0;
    if (current_window_size(c.egl, &w, &h)) c.targets->set_window_size(w, h);
  }
  t_ctx = c.initialized ? &c : nullptr;
  t_draw = c.initialized ? c.counter.get() : nullptr;
  t_probe = t_ctx && t_ctx->probes ? t_ctx->probes->drawing() : nullptr;
}

void context_will_change(void* handle) {
  // A context that stops being current here cannot be asked later from this thread: harvest
  // what the GPU has finished while it still is (no waiting).
  if (t_ctx && t_ctx->handle != handle) {
    const AppSignalsDeferred deferred;
    if (t_ctx->counter) t_ctx->counter->suspend();
    flush_pending_frames(*t_ctx, FlushMode::kCollect);
    release_app_signals();  // this thread's probe frame stops here
    // Instrumentation counters cannot be read from another thread or context: read them now.
    instrumentation_release(*t_ctx);
  }
}

void context_destroyed(void* handle) {
  // Ends after the lock: a handler run at its end may destroy a context (app_signals.hpp).
  const AppSignalsDeferred deferred;
  Registry& r = registry();
  std::lock_guard lock(r.mu);
  bool current_here = t_ctx && t_ctx->handle == handle;
  if (current_here && t_ctx->counter) t_ctx->counter->suspend();
  if (current_here) instrumentation_release(*t_ctx);  // called before the real destroy
  if (current_here && t_ctx->probes) t_ctx->probes->abandon_frame();
  retire(r, handle, current_here);
  // A destroyed context that is still current stays usable (GLX) until released; we stop
  // counting on it, since its queries are about to vanish.
  if (current_here) {
    t_ctx = nullptr;
    t_draw = nullptr;
    t_probe = nullptr;
    release_app_signals();
  }
}

void display_terminated(void* display) {
  Registry& r = registry();
  std::lock_guard lock(r.mu);
  std::vector<void*> gone;
  for (auto& [h, c] : r.live)
    if (c->display == display) gone.push_back(h);
  for (void* h : gone) retire(r, h, t_ctx && t_ctx->handle == h);
  if (t_ctx && t_ctx->display == display) {
    t_ctx = nullptr;
    t_draw = nullptr;
  }
}

void for_each_context(void (*fn)(ContextState&)) {
  Registry& r = registry();
  std::lock_guard lock(r.mu);
  for (auto& [h, c] : r.live) fn(*c);
}

PassId pass_of_program(ShareGroup& g, GLuint program) {
  auto it = g.programs.find(program);
  if (it != g.programs.end() && it->second.linked) return it->second.pass;
  // A program we never saw linked (it cannot draw; GL raises the error): name it by its id.
  return fnv1a_u64(program, fnv1a("unlinked-program"));
}

void apply_configuration(ContextState& c, const Levels& config) {
  if (c.config == config && c.config.count > 0) return;
  c.config = config;
  if (c.counter) c.counter->set_configuration(format_levels(config).c_str());
  if (c.bound_variants) {
    bind_program(c);
    if (c.instrumentation) bind_counters(c);  // the variant drawn now counts under its own name
  }
  bind_pipeline_stages(c);
  if (c.targets) c.targets->set_configuration(config);
  update_pass(c);
}

bool pipeline_skips(ContextState& c) {
  auto it = c.pipeline_stages.find(c.pipeline);
  if (it == c.pipeline_stages.end()) return false;
  std::lock_guard lock(c.group->mu);
  for (GLuint p : it->second) {
    auto info = p ? c.group->programs.find(p) : c.group->programs.end();
    if (info != c.group->programs.end() && info->second.variants && !info->second.variants->at(c.config).draws)
      return true;
  }
  return false;
}

void update_pass(ContextState& c) {
  if (!c.counter) return;
  PassId pass = kFixedFunctionPass;
  bool skip = false;
  if (c.bound_variants) {
    const Variant& v = c.bound_variants->at(c.config);
    pass = v.pass_hash;
    skip = !v.draws;
  } else if (c.program) {
    std::lock_guard lock(c.group->mu);
    pass = pass_of_program(*c.group, c.program);
  } else if (c.pipeline) {
    auto it = c.pipeline_stages.find(c.pipeline);
    if (it != c.pipeline_stages.end()) {
      std::lock_guard lock(c.group->mu);
      uint64_t h = fnv1a("pipeline");
      for (GLuint p : it->second) {
        // A stage drawn through a variant is named by the variant, as a program is.
        PassId stage = p ? pass_of_program(*c.group, p) : 0;
        auto info = p ? c.group->programs.find(p) : c.group->programs.end();
        if (info != c.group->programs.end() && info->second.variants)
          stage = info->second.variants->at(c.config).pass_hash;
        h = fnv1a_u64(stage, h);
      }
      pass = h;
    }
    skip = pipeline_skips(c);
  }
  c.counter->set_pass(pass);
  c.counter->set_skipping(skip);
}

}  // namespace glbudget
