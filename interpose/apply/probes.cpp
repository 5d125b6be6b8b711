#include "probes.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "app_signals.hpp"
#include "app_space_uniforms.hpp"
#include "apply_gl.hpp"
#include "context_state.hpp"
#include "gl_errors.hpp"
#include "governing.hpp"
#include "hook_table.hpp"
#include "messages.hpp"
#include "glbudget/loop/power_feedback.hpp"
#include "glbudget/loop/probe_order.hpp"
#include "glbudget/loop/probe_overhead.hpp"
#include "glbudget/quality/ssim.hpp"
#include "options.hpp"
#include "probe_ssim.hpp"
#include "render_targets.hpp"

namespace glbudget {

thread_local ProbeFrames* t_probe __attribute__((tls_model("initial-exec"))) = nullptr;

const ProbeSettings& probe_settings() {
  static const ProbeSettings settings = [] {
    ProbeSettings s;
    const Options& o = options();
    // Probes measure what the governor chooses by: on by default only when it governs.
    s.period = o.probe_period >= 0 ? static_cast<uint64_t>(o.probe_period) : governor_steering() ? 10 : 0;
    // The two frames after a probe read it back and finish its work: their power is the
    // probe's too (ProbeOverhead). Probing more often than every fourth frame leaves the
    // governor no frame whose power it can fit.
    if (governor_steering() && s.period >= 1 && s.period <= 3) {
      say("GLBUDGET_PROBE_PERIOD=" + std::to_string(s.period) +
          " leaves no frame whose power the budget can be kept by (each is a probe or one of the two after it); "
          "probing every 4 frames");
      s.period = 4;
    }
    s.settled_factor = o.probe_period >= 0 ? 1 : 6;
    s.stretchable = o.probe_period < 0;
    s.dump_dir = o.dump_probes;
    return s;
  }();
  return settings;
}

namespace {
std::atomic<uint64_t> g_period_wanted{0}, g_period_in_force{0};
std::atomic<bool> g_bursts_spaced{false};
std::atomic<int> g_streams_fit{0};
std::atomic<uint64_t> g_selection_due{0}, g_select_frames{0};  // set_probe_selection_due
std::atomic<bool> g_transitioning{false};
std::atomic<int> g_sweep_streams{0}, g_sweepable_streams{0};
std::atomic<float> g_pass_error[kMaxPasses];  // set_probe_pass_error
}  // namespace

void set_probe_pass_error(size_t pass, double error) {
  if (pass < static_cast<size_t>(kMaxPasses))
    g_pass_error[pass].store(static_cast<float>(error), std::memory_order_relaxed);
}

void set_probe_period_wanted(uint64_t frames, bool bursts_too, int streams_fit) {
  g_period_wanted.store(frames, std::memory_order_relaxed);
  g_bursts_spaced.store(bursts_too, std::memory_order_relaxed);
  g_streams_fit.store(streams_fit, std::memory_order_relaxed);
}
uint64_t probe_period_in_force() { return g_period_in_force.load(std::memory_order_relaxed); }
int probe_sweep_streams() { return g_sweep_streams.load(std::memory_order_relaxed); }
int probe_sweepable_streams() { return g_sweepable_streams.load(std::memory_order_relaxed); }

void set_probe_selection_due(uint64_t frame, uint64_t select_frames, bool transitioning) {
  g_selection_due.store(frame, std::memory_order_relaxed);
  g_select_frames.store(select_frames, std::memory_order_relaxed);
  g_transitioning.store(transitioning, std::memory_order_relaxed);
}

namespace {

// Entry points beyond the apply layer's table (apply_gl.hpp), resolved to the driver.
struct ProbeGl {
  void(APIENTRYP GetTexLevelParameteriv)(GLenum, GLint, GLenum, GLint*) = nullptr;
  void(APIENTRYP TexStorage2D)(GLenum, GLsizei, GLenum, GLsizei, GLsizei) = nullptr;
  void(APIENTRYP TexStorage3D)(GLenum, GLsizei, GLenum, GLsizei, GLsizei, GLsizei) = nullptr;
  void(APIENTRYP FramebufferTexture)(GLenum, GLenum, GLuint, GLint) = nullptr;  // GL 3.2, ES 3.2
  void(APIENTRYP TexStorage2DMultisample)(GLenum, GLsizei, GLenum, GLsizei, GLsizei,
                                          GLboolean) = nullptr;  // GL 4.3, ES 3.1
  void(APIENTRYP GetRenderbufferParameteriv)(GLenum, GLenum, GLint*) = nullptr;
  void(APIENTRYP DrawBuffers)(GLsizei, const GLenum*) = nullptr;
  void(APIENTRYP GetQueryiv)(GLenum, GLenum, GLint*) = nullptr;
  void(APIENTRYP GenBuffers)(GLsizei, GLuint*) = nullptr;
  void(APIENTRYP DeleteBuffers)(GLsizei, const GLuint*) = nullptr;
  void(APIENTRYP BindBuffer)(GLenum, GLuint) = nullptr;
  void(APIENTRYP BufferData)(GLenum, GLsizeiptr, const void*, GLenum) = nullptr;
  void(APIENTRYP ReadPixels)(GLint, GLint, GLsizei, GLsizei, GLenum, GLenum, void*) = nullptr;
  void*(APIENTRYP MapBufferRange)(GLenum, GLintptr, GLsizeiptr, GLbitfield) = nullptr;
  GLboolean(APIENTRYP UnmapBuffer)(GLenum) = nullptr;
  GLsync(APIENTRYP FenceSync)(GLenum, GLbitfield) = nullptr;
  GLenum(APIENTRYP ClientWaitSync)(GLsync, GLbitfield, GLuint64) = nullptr;
  void(APIENTRYP DeleteSync)(GLsync) = nullptr;
  void(APIENTRYP PixelStorei)(GLenum, GLint) = nullptr;
  void(APIENTRYP GetIntegeri_v)(GLenum, GLuint, GLint*) = nullptr;
  void(APIENTRYP GetBooleanv)(GLenum, GLboolean*) = nullptr;
  void(APIENTRYP GetBooleani_v)(GLenum, GLuint, GLboolean*) = nullptr;  // GL 3.0, ES 3.0
  void(APIENTRYP GenerateMipmap)(GLenum) = nullptr;
  bool complete = false;
};

const ProbeGl& pgl() {
  static const ProbeGl g = [] {
    ProbeGl p;
    auto load = [](auto& fn, const char* name) {
      fn = reinterpret_cast<std::remove_reference_t<decltype(fn)>>(resolve_gl(name));
    };
    load(p.GetTexLevelParameteriv, "glGetTexLevelParameteriv");
    load(p.TexStorage2D, "glTexStorage2D");
    load(p.TexStorage3D, "glTexStorage3D");
    load(p.FramebufferTexture, "glFramebufferTexture");
    load(p.TexStorage2DMultisample, "glTexStorage2DMultisample");
    load(p.GetRenderbufferParameteriv, "glGetRenderbufferParameteriv");
    load(p.DrawBuffers, "glDrawBuffers");
    load(p.GetQueryiv, "glGetQueryiv");
    load(p.GenBuffers, "glGenBuffers");
    load(p.DeleteBuffers, "glDeleteBuffers");
    load(p.BindBuffer, "glBindBuffer");
    load(p.BufferData, "glBufferData");
    load(p.ReadPixels, "glReadPixels");
    load(p.MapBufferRange, "glMapBufferRange");
    load(p.UnmapBuffer, "glUnmapBuffer");
    load(p.FenceSync, "glFenceSync");
    load(p.ClientWaitSync, "glClientWaitSync");
    load(p.DeleteSync, "glDeleteSync");
    load(p.PixelStorei, "glPixelStorei");
    load(p.GetIntegeri_v, "glGetIntegeri_v");
    load(p.GetBooleanv, "glGetBooleanv");
    load(p.GetBooleani_v, "glGetBooleani_v");
    load(p.GenerateMipmap, "glGenerateMipmap");
    const ApplyGl& a = agl();
    p.complete = a.ActiveTexture && a.GetTexParameteriv && a.TexParameteri && p.GetTexLevelParameteriv &&
                 p.TexStorage2D && p.GetRenderbufferParameteriv && p.DrawBuffers && p.GenBuffers && p.DeleteBuffers &&
                 p.BindBuffer && p.BufferData && p.ReadPixels && p.MapBufferRange && p.UnmapBuffer && p.FenceSync &&
                 p.ClientWaitSync && p.DeleteSync && p.PixelStorei;
    return p;
  }();
  return g;
}

constexpr int kMaxColorAttachments = 8;
constexpr int kMaxUnits = 32;      // texture units looked at for redirection
constexpr size_t kMaxPending = 4;  // probe read-backs in flight
// s0 and the s_i^lmax of one probe frame: one pass a frame, or every pass in the scene at once
// (GLBUDGET_PROBE_SWEEP): s0 and seven passes, or eight where s0 is shown.
constexpr int kMaxStreams = 8;
// GLBUDGET_PROBE_SWEEP: frames a sweep is drawn ahead of the selection due, so that its
// read-back and comparison reach the governor before it decides that frame (probe captures are
// measured in frame order, apply/governing.cpp).
constexpr uint64_t kSweepLead = 5;
// What a sweep of the demo's four to six passes cost against a probe of one pass, each a probe
// frame every 60 frames unpaced (docs/evaluation/probes/probe-sweeps.md): 1.2-1.7 times; so the
// settled period, where it sets the longest gap between sweeps, is doubled.
constexpr int kSweepCostInProbes = 2;

GLint get(GLenum pname) {
  GLint v = 0;
  agl().GetIntegerv(pname, &v);
  return v;
}

// The texture kinds a framebuffer draws into (TargetScaler::texture_kind): index 0 is 2D, the
// last multisample 2D, the others layered (a layer or a cube map's face attached).
constexpr GLenum kKinds[] = {GL_TEXTURE_2D, GL_TEXTURE_2D_ARRAY, GL_TEXTURE_CUBE_MAP, GL_TEXTURE_CUBE_MAP_ARRAY,
                             GL_TEXTURE_2D_MULTISAMPLE};
constexpr int kKindCount = 5;
int kind_index(GLenum kind) {
  for (int k = 0; k < kKindCount; ++k)
    if (kKinds[k] == kind) return k;
  return -1;
}

struct ShadowImage {
  GLenum point = 0;
  bool renderbuffer = false;
  GLuint app = 0;     // the app's texture or renderbuffer
  GLuint shadow = 0;  // ours, same format, at the stream's scale
  GLint format = 0;
  GLsizei samples = 0;
  GLsizei levels = 1;  // a texture's mip levels, as many as the app's (its glGenerateMipmap is repeated)
  // A layered texture's: its kind, its layers (a cube map's six faces), the one attached (-1:
  // all, a geometry shader choosing). Its shadow is the stream's (Stream::layered), shared by
  // every framebuffer drawing into it.
  GLenum kind = GL_TEXTURE_2D;
  GLsizei layers = 1;
  GLint layer = 0;
  bool layered() const { return !renderbuffer && kind != GL_TEXTURE_2D && kind != GL_TEXTURE_2D_MULTISAMPLE; }
};

// A stream's shadow of an array or cube-map texture of the app's: every layer at the stream's
// scale, each filled with the app's content at its first use in a probe frame.
struct LayeredShadow {
  GLuint texture = 0;
  GLenum kind = 0;
  GLint format = 0;
  int width = 0, height = 0;
  GLsizei layers = 0;
  std::vector<uint64_t> copied_frame;  // per layer
  std::vector<uint64_t> copied_call;   // per layer: the probe frame's call that copied it in
};

// A shadow texture standing in for the app's in a stream's draws, and its kind.
struct StandIn {
  GLuint texture = 0;
  GLenum kind = GL_TEXTURE_2D;
};

struct Shadow {
  GLuint fbo = 0;
  int app_width = 0, app_height = 0;  // the app's size of its images
  int width = 0, height = 0;          // the shadow's
  std::vector<ShadowImage> images;
  uint64_t initialized_frame = 0;  // content copied from the app's this frame
  uint64_t filled_call = 0;        // the probe frame's call before which it was first filled
  uint64_t described_changes = 0;  // TargetScaler::attachment_changes() when described
  bool usable = false;
};

struct Stream {
  Levels config;
  std::unordered_map<GLuint, Shadow> shadows;         // by the app's framebuffer (0: the window)
  std::unordered_map<GLuint, StandIn> textures;       // drawn this frame: app texture -> shadow
  std::unordered_map<GLuint, LayeredShadow> layered;  // by the app's texture
  bool complete = true;
  // A stream starts its frame following: as long as every call so far draws the same in it as
  // in the app's frame (follows_app) or as in stream 0 (follows_first), it draws nothing and its
  // images are that one's. At the first call it would draw differently it forks: from then on it
  // draws, each of its shadows starting from its lead's image (-1: the app's, 0: stream 0's).
  bool forked = true, follows_app = false, follows_first = false;
  int lead = -1;
  uint64_t fork_call = 0;  // the probe frame's call it forked at (1: the first; 0: drawn whole)
};

// A probe frame's comparison queued in the context's compute shaders.
struct GpuComparison {
  size_t a = 0, b = 0;  // images
  uint64_t ticket = 0;
};

// A probe frame on its way to the governor: its comparisons on the GPU, its images read back
// (where they are compared on the CPU or dumped), or both.
struct Readback {
  ProbeCapture capture;
  std::vector<GpuComparison> comparisons;
  std::vector<GLuint> buffers;
  GLsync fence = nullptr;
};

}  // namespace

// The shadow of an app texture gets immutable storage, which takes sized formats only: an app
// texture specified with an unsized one (GL_RGBA, as GLES 2-era code does) gets the sized one
// (sized_internal_format); a depth texture the format of the bits the driver gave it (a depth
// blit between the two needs the same format on both sides), 0 where none fits.
static GLint sized_depth_format(GLint depth_bits, GLint stencil_bits, bool floating) {
  if (stencil_bits > 0) return floating ? GL_DEPTH32F_STENCIL8 : GL_DEPTH24_STENCIL8;
  if (floating) return GL_DEPTH_COMPONENT32F;
  switch (depth_bits) {
    case 16:
      return GL_DEPTH_COMPONENT16;
    case 24:
      return GL_DEPTH_COMPONENT24;
    case 32:
      return GL_DEPTH_COMPONENT32;
    default:
      return 0;
  }
}

struct ProbeFrames::Impl {
  ContextState& c;
  uint64_t frame = 0;  // the probe frame being drawn (0: none)
  uint64_t last_probe = 0;
  int stream_count = 0;
  Stream streams[kMaxStreams];
  uint64_t passes_drawn = ~uint64_t{0};  // in the last probe frame (all before the first)
  uint64_t passes_now = 0;
  uint64_t call = 0;               // the probe frame's draws, clears and blits so far
  bool duplicating_clear = false;  // the duplicate in progress is a clear's
  // Shadow images released during a probe frame: a stream's later draws may still sample
  // them (an app re-attaching another texture to a framebuffer it drew this frame).
  std::vector<GLuint> retired_textures;
  size_t next_pass = 0;               // round robin over the (pass, level) pairs probed
  std::vector<uint64_t> pair_probed;  // per (pass, level) pair: the frame it was last probed at
  std::vector<loop::ProbeCandidate> candidates;
  bool disabled = false;

  // The duplicate in progress.
  int stream = -1;
  GLint saved_draw_fbo = 0, saved_read_fbo = 0, saved_active = 0;
  GLint saved_viewport[4] = {}, saved_scissor[4] = {};
  Levels saved_config;
  // The app's textures on each unit, by kind (kKinds); only the kinds some stream has a
  // shadow of are asked (bit k of `kinds`).
  GLint unit_texture[kMaxUnits][kKindCount] = {};
  unsigned kinds = 1;
  int units = 0;
  bool redirected[kMaxUnits][kKindCount] = {};

  // Capture targets: 0 the app's image, then one per stream, window-sized textures (the GPU
  // SSIM samples them).
  GLuint capture_fbo[kMaxStreams + 1] = {}, capture_texture[kMaxStreams + 1] = {};
  int capture_width = 0, capture_height = 0, capture_count = 0;
  bool captured[kMaxStreams + 1] = {};
  std::vector<Readback> pending;
  // The context's GPU SSIM (apply/probe_ssim.hpp), made at the first probe frame; null: the
  // governor thread compares read-back images.
  std::unique_ptr<GpuSsim> gpu;
  bool gpu_made = false;

  explicit Impl(ContextState& ctx) : c(ctx) {}

  TargetScaler* targets() const { return c.targets.get(); }
  GLuint app_draw_fbo() const { return targets()->app_draw_framebuffer(); }

  // GL 4.2 / GLES 3.1, or desktop GL 3.2 with GL_ARB_texture_storage (NVIDIA answers a request
  // for 3.3 with exactly 3.3, and the extension): immutable storage for the shadows.
  bool probe_possible() const {
    if (disabled || !targets() || !pgl().complete) return false;
    if (!storage_known) {
      storage_known = true;
      storage = at_least(4, 2, 3, 1) ||
                (!c.caps.gles && at_least(3, 2, 0, 0) && has_extension(c.caps, "GL_ARB_texture_storage"));
    }
    return storage;
  }
  mutable bool storage_known = false, storage = false;
  // Multisampled shadows: GL 4.3 / GLES 3.1, or GL_ARB_texture_storage_multisample.
  bool multisample_storage() const {
    return at_least(4, 3, 3, 1) || (!c.caps.gles && has_extension(c.caps, "GL_ARB_texture_storage_multisample"));
  }

  void release_shadow(Shadow& s) {
    const ApplyGl& g = agl();
    for (ShadowImage& im : s.images) {
      if (im.renderbuffer)
        g.DeleteRenderbuffers(1, &im.shadow);
      else if (im.layered())  // the stream's, shared
        continue;
      else if (frame)
        retired_textures.push_back(im.shadow);
      else
        g.DeleteTextures(1, &im.shadow);
    }
    if (s.fbo) g.DeleteFramebuffers(1, &s.fbo);
    s = Shadow{};
  }

  void release_stream(Stream& st) {
    for (auto& [app, shadow] : st.shadows) release_shadow(shadow);
    st.shadows.clear();
    for (auto& [app, l] : st.layered)
      if (l.texture) agl().DeleteTextures(1, &l.texture);
    st.layered.clear();
    st.textures.clear();
  }

  // The app's attachments of its framebuffer `app` (bound for drawing now), or of the window.
  bool describe(GLuint app, double stream_scale, Shadow& out) {
    const ApplyGl& g = agl();
    const ProbeGl& p = pgl();
    TargetScaler& t = *targets();
    if (app == 0) {
      out.app_width = t.window_width();
      out.app_height = t.window_height();
      if (out.app_width <= 0 || out.app_height <= 0) return false;
      // As many samples as the window: the best stream must antialias as the app's image does.
      const GLsizei samples = t.window_samples();
      // Depth and stencil as the window's own where it is drawn unscaled: a blit of depth or
      // stencil between different formats is an error (the stand-in's is GL_DEPTH24_STENCIL8).
      const std::pair<GLenum, GLint> stand_in{GL_DEPTH_STENCIL_ATTACHMENT, GL_DEPTH24_STENCIL8};
      const auto [point, format] = t.window_scaled() ? stand_in : window_depth_stencil();
      out.images = {{GL_COLOR_ATTACHMENT0, true, 0, 0, GL_RGBA8, samples}, {point, true, 0, 0, format, samples}};
    } else {
      double sx = 1.0, sy = 1.0;
      t.stored_scale(app, &sx, &sy);
      int stored_w = 0, stored_h = 0;
      std::vector<GLenum> points;
      for (int i = 0; i < kMaxColorAttachments; ++i) points.push_back(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i));
      points.push_back(GL_DEPTH_ATTACHMENT);
      points.push_back(GL_STENCIL_ATTACHMENT);
      for (GLenum point : points) {
        GLint type = GL_NONE, name = 0;
        g.GetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, point, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
        if (type == GL_NONE) continue;
        g.GetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, point, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
        ShadowImage im;
        im.point = point;
        im.app = static_cast<GLuint>(name);
        im.renderbuffer = type == GL_RENDERBUFFER;
        if (point == GL_STENCIL_ATTACHMENT) {
          bool shared = false;
          for (ShadowImage& other : out.images)
            if (other.point == GL_DEPTH_ATTACHMENT && other.app == im.app && other.renderbuffer == im.renderbuffer) {
              other.point = GL_DEPTH_STENCIL_ATTACHMENT;
              shared = true;
            }
          if (shared) continue;
        }
        GLint w = 0, h = 0;
        if (im.renderbuffer) {
          const GLint bound = get(GL_RENDERBUFFER_BINDING);
          g.BindRenderbuffer(GL_RENDERBUFFER, im.app);
          p.GetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_INTERNAL_FORMAT, &im.format);
          p.GetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_WIDTH, &w);
          p.GetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_HEIGHT, &h);
          p.GetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_SAMPLES, &im.samples);
          g.BindRenderbuffer(GL_RENDERBUFFER, static_cast<GLuint>(bound));
        } else {
          // Level 0 of a 2D or multisample texture, a layer of an array or a cube map's face, or
          // all of them (a layered attachment: a geometry shader choosing the layer).
          GLint level = 0, layered = GL_FALSE, face = 0, layer = 0;
          g.GetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, point, GL_FRAMEBUFFER_ATTACHMENT_TEXTURE_LEVEL,
                                                &level);
          g.GetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, point,
                                                GL_FRAMEBUFFER_ATTACHMENT_TEXTURE_CUBE_MAP_FACE, &face);
          g.GetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, point, GL_FRAMEBUFFER_ATTACHMENT_TEXTURE_LAYER,
                                                &layer);
          if (at_least(3, 2, 3, 2))
            g.GetFramebufferAttachmentParameteriv(GL_DRAW_FRAMEBUFFER, point, GL_FRAMEBUFFER_ATTACHMENT_LAYERED,
                                                  &layered);
          if (level != 0) return false;
          // The kind the scaler saw the texture made as, else taken to be 2D; a texture of
          // another kind cannot be bound to it: the error says so (GL_TEXTURE_TARGET, the direct
          // question, is not answered in compatibility profiles). Called within the shim's own
          // GL work (prepare): errors here are its own.
          const GLenum known = t.kind_of(im.app);
          im.kind = known ? known : GL_TEXTURE_2D;
          const int k = kind_index(im.kind);
          if (k < 0 || (im.layered() && (!p.TexStorage3D || !g.FramebufferTextureLayer))) return false;
          if (im.kind == GL_TEXTURE_2D_MULTISAMPLE && (!p.TexStorage2DMultisample || !multisample_storage()))
            return false;
          if (!im.layered() && (face != 0 || layer != 0 || layered)) return false;
          if (layered && !p.FramebufferTexture) return false;
          im.layer = layered                                       ? -1
                     : im.kind == GL_TEXTURE_CUBE_MAP && face != 0 ? face - GL_TEXTURE_CUBE_MAP_POSITIVE_X
                                                                   : layer;
          const GLint bound = get(TargetScaler::binding_of(kKinds[k]));
          drain_gl_errors();
          g.BindTexture(im.kind, im.app);
          if (!drain_gl_errors().empty()) {  // a texture of another target: GL_INVALID_OPERATION
            g.BindTexture(im.kind, static_cast<GLuint>(bound));
            return false;
          }
          // Level queries of a cube map go to a face.
          const GLenum of = im.kind == GL_TEXTURE_CUBE_MAP ? GL_TEXTURE_CUBE_MAP_POSITIVE_X : im.kind;
          p.GetTexLevelParameteriv(of, 0, GL_TEXTURE_INTERNAL_FORMAT, &im.format);
          if (im.format == GL_DEPTH_COMPONENT || im.format == GL_DEPTH_STENCIL) {
            GLint depth_bits = 0, stencil_bits = 0, depth_type = GL_NONE;
            p.GetTexLevelParameteriv(of, 0, GL_TEXTURE_DEPTH_SIZE, &depth_bits);
            p.GetTexLevelParameteriv(of, 0, GL_TEXTURE_STENCIL_SIZE, &stencil_bits);
            p.GetTexLevelParameteriv(of, 0, GL_TEXTURE_DEPTH_TYPE, &depth_type);
            im.format = sized_depth_format(depth_bits, stencil_bits, depth_type == GL_FLOAT);
          } else {
            im.format = sized_internal_format(im.format);
          }
          p.GetTexLevelParameteriv(of, 0, GL_TEXTURE_WIDTH, &w);
          p.GetTexLevelParameteriv(of, 0, GL_TEXTURE_HEIGHT, &h);
          if (im.kind == GL_TEXTURE_CUBE_MAP) {
            im.layers = 6;
          } else if (im.layered()) {
            p.GetTexLevelParameteriv(of, 0, GL_TEXTURE_DEPTH, &im.layers);
          } else if (im.kind == GL_TEXTURE_2D_MULTISAMPLE) {
            p.GetTexLevelParameteriv(of, 0, GL_TEXTURE_SAMPLES, &im.samples);
          }
          // Its levels only where the app fills them by glGenerateMipmap, which the duplicate
          // repeats; levels it draws one by one (framebuffers of level > 0 are not shadowed)
          // would stay undefined in the shadow, where level 0 alone stands for them.
          im.levels = im.kind == GL_TEXTURE_2D && generated_mipmaps.count(im.app) ? texture_levels() : 1;
          g.BindTexture(im.kind, static_cast<GLuint>(bound));
          if (im.layer < -1 || im.layer >= im.layers) return false;
        }
        if (w <= 0 || h <= 0 || im.format == 0) return false;
        if (stored_w == 0) stored_w = w, stored_h = h;
        out.images.push_back(im);
      }
      if (out.images.empty()) return false;
      out.app_width = static_cast<int>(stored_w / sx + 0.5);
      out.app_height = static_cast<int>(stored_h / sy + 0.5);
    }
    out.width = std::max(1, static_cast<int>(out.app_width * stream_scale + 0.5));
    out.height = std::max(1, static_cast<int>(out.app_height * stream_scale + 0.5));
    return true;
  }

  std::unordered_set<GLuint> generated_mipmaps;  // app textures seen in glGenerateMipmap

  // The mip levels of the texture bound to GL_TEXTURE_2D that sampling can reach: its
  // immutable levels, or those specified from level 0 on, up to its maximum level.
  GLsizei texture_levels() {
    const ProbeGl& p = pgl();
    GLint immutable = GL_FALSE, levels = 0, max_level = 1000;
    const ApplyGl& g = agl();
    g.GetTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_IMMUTABLE_FORMAT, &immutable);
    if (immutable) {
      g.GetTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_IMMUTABLE_LEVELS, &levels);
      return std::max(1, levels);
    }
    g.GetTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, &max_level);
    for (levels = 1; levels <= std::min(max_level, 15); ++levels) {
      GLint width = 0;
      p.GetTexLevelParameteriv(GL_TEXTURE_2D, levels, GL_TEXTURE_WIDTH, &width);
      if (width <= 0) break;
    }
    return levels;
  }

  // The context is at least desktop GL major.minor, or GLES es_major.es_minor.
  bool at_least(int major, int minor, int es_major, int es_minor) const {
    const int have = c.caps.major * 10 + c.caps.minor;
    return c.caps.gles ? have >= es_major * 10 + es_minor : have >= major * 10 + minor;
  }

  // `to` (bound to `kind`) sampled as the app's `from` is: its filtering, wrapping, depth
  // comparison and levels. Leaves `to` bound.
  static void copy_sampling(GLenum kind, GLuint from, GLuint to) {
    const ApplyGl& g = agl();
    static const GLenum kParams[] = {GL_TEXTURE_MIN_FILTER, GL_TEXTURE_MAG_FILTER,   GL_TEXTURE_WRAP_S,
                                     GL_TEXTURE_WRAP_T,     GL_TEXTURE_COMPARE_MODE, GL_TEXTURE_COMPARE_FUNC,
                                     GL_TEXTURE_BASE_LEVEL, GL_TEXTURE_MAX_LEVEL};
    for (GLenum param : kParams) {
      GLint v = 0;
      g.BindTexture(kind, from);
      g.GetTexParameteriv(kind, param, &v);
      g.BindTexture(kind, to);
      g.TexParameteri(kind, param, v);
    }
  }

  // The stream's shadow of a layered app texture at the shadow's size, made (again, where the
  // stream's scale or the app's texture changed) if needed.
  LayeredShadow& layered_shadow(Stream& st, const ShadowImage& im, int width, int height) {
    LayeredShadow& l = st.layered[im.app];
    if (l.texture && l.kind == im.kind && l.format == im.format && l.width == width && l.height == height &&
        l.layers == im.layers)
      return l;
    const ApplyGl& g = agl();
    if (l.texture) g.DeleteTextures(1, &l.texture);
    const GLint bound = get(TargetScaler::binding_of(im.kind));
    l = LayeredShadow{};
    g.GenTextures(1, &l.texture);
    g.BindTexture(im.kind, l.texture);
    if (im.kind == GL_TEXTURE_CUBE_MAP)
      pgl().TexStorage2D(GL_TEXTURE_CUBE_MAP, 1, static_cast<GLenum>(im.format), width, height);
    else
      pgl().TexStorage3D(im.kind, 1, static_cast<GLenum>(im.format), width, height, im.layers);
    copy_sampling(im.kind, im.app, l.texture);
    g.BindTexture(im.kind, static_cast<GLuint>(bound));
    l.kind = im.kind;
    l.format = im.format;
    l.width = width;
    l.height = height;
    l.layers = im.layers;
    l.copied_frame.assign(static_cast<size_t>(im.layers), 0);
    l.copied_call.assign(static_cast<size_t>(im.layers), 0);
    return l;
  }

  // Creates the shadow's images and framebuffer (the app's framebuffer is bound for drawing).
  bool build(Stream& st, Shadow& s, GLuint app) {
    const ApplyGl& g = agl();
    const ProbeGl& p = pgl();
    const GLint texture = get(GL_TEXTURE_BINDING_2D), renderbuffer = get(GL_RENDERBUFFER_BINDING);
    GLenum draw_buffers[kMaxColorAttachments];
    GLsizei draw_count = 0;
    if (app == 0) {
      draw_buffers[draw_count++] = GL_COLOR_ATTACHMENT0;
    } else {
      for (int i = 0; i < kMaxColorAttachments; ++i)
        draw_buffers[draw_count++] = static_cast<GLenum>(get(GL_DRAW_BUFFER0 + i));
    }
    g.GenFramebuffers(1, &s.fbo);
    g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, s.fbo);
    for (ShadowImage& im : s.images) {
      if (im.renderbuffer) {
        g.GenRenderbuffers(1, &im.shadow);
        g.BindRenderbuffer(GL_RENDERBUFFER, im.shadow);
        g.RenderbufferStorageMultisample(GL_RENDERBUFFER, im.samples, static_cast<GLenum>(im.format), s.width,
                                         s.height);
        g.FramebufferRenderbuffer(GL_DRAW_FRAMEBUFFER, im.point, GL_RENDERBUFFER, im.shadow);
      } else if (im.layered()) {
        im.shadow = layered_shadow(st, im, s.width, s.height).texture;
        if (im.layer < 0)
          p.FramebufferTexture(GL_DRAW_FRAMEBUFFER, im.point, im.shadow, 0);
        else
          attach_texture_layer(GL_DRAW_FRAMEBUFFER, im.point, im.kind, im.shadow, im.layer);
      } else if (im.kind == GL_TEXTURE_2D_MULTISAMPLE) {
        const GLint bound = get(GL_TEXTURE_BINDING_2D_MULTISAMPLE);
        g.GenTextures(1, &im.shadow);
        g.BindTexture(GL_TEXTURE_2D_MULTISAMPLE, im.shadow);
        p.TexStorage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, im.samples, static_cast<GLenum>(im.format), s.width,
                                  s.height, GL_TRUE);
        g.BindTexture(GL_TEXTURE_2D_MULTISAMPLE, static_cast<GLuint>(bound));
        g.FramebufferTexture2D(GL_DRAW_FRAMEBUFFER, im.point, GL_TEXTURE_2D_MULTISAMPLE, im.shadow, 0);
      } else {
        g.GenTextures(1, &im.shadow);
        g.BindTexture(GL_TEXTURE_2D, im.shadow);
        // The shadow's size may hold fewer levels than the app's.
        p.TexStorage2D(GL_TEXTURE_2D, std::min(im.levels, full_mip_levels(s.width, s.height)),
                       static_cast<GLenum>(im.format), s.width, s.height);
        copy_sampling(GL_TEXTURE_2D, im.app, im.shadow);
        g.FramebufferTexture2D(GL_DRAW_FRAMEBUFFER, im.point, GL_TEXTURE_2D, im.shadow, 0);
      }
    }
    p.DrawBuffers(draw_count, draw_buffers);
    g.BindTexture(GL_TEXTURE_2D, static_cast<GLuint>(texture));
    g.BindRenderbuffer(GL_RENDERBUFFER, static_cast<GLuint>(renderbuffer));
    s.usable = true;
    return true;
  }

  // The layers of a layered image (the attached one, or all) not yet copied this probe frame,
  // from the app's texture at its stored size (or the lead stream's, where it had the layer
  // before this call) into the stream's at the shadow's. A layer the stream drew earlier in
  // the frame keeps what it drew. Binds its own framebuffers.
  GLuint layer_fbo[2] = {0, 0};
  void copy_layers(Stream& st, const ShadowImage& im, int src_w, int src_h, int dst_w, int dst_h) {
    const ApplyGl& g = agl();
    LayeredShadow& l = st.layered[im.app];
    const bool color =
        im.point != GL_DEPTH_ATTACHMENT && im.point != GL_STENCIL_ATTACHMENT && im.point != GL_DEPTH_STENCIL_ATTACHMENT;
    const GLenum point = color ? GL_COLOR_ATTACHMENT0 : im.point;
    const GLbitfield mask = color                               ? GL_COLOR_BUFFER_BIT
                            : im.point == GL_DEPTH_ATTACHMENT   ? GL_DEPTH_BUFFER_BIT
                            : im.point == GL_STENCIL_ATTACHMENT ? GL_STENCIL_BUFFER_BIT
                                                                : GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT;
    if (!layer_fbo[0]) g.GenFramebuffers(2, layer_fbo);
    GLint first = im.layer < 0 ? 0 : im.layer, last = im.layer < 0 ? im.layers - 1 : im.layer;
    // A stream that forked after calls it did not draw may meet the texture first with layers
    // its lead drew before: all of them, then, from where they are.
    if (st.fork_call > 1 &&
        std::none_of(l.copied_frame.begin(), l.copied_frame.end(), [&](uint64_t copied) { return copied == frame; })) {
      first = 0;
      last = im.layers - 1;
    }
    const LayeredShadow* lead = nullptr;
    if (st.lead == 0 && &st != &streams[0]) {
      const auto it = streams[0].layered.find(im.app);
      if (it != streams[0].layered.end() && it->second.texture && it->second.kind == im.kind) lead = &it->second;
    }
    for (GLint layer = first; layer <= last; ++layer) {
      uint64_t& copied = l.copied_frame[static_cast<size_t>(layer)];
      if (copied == frame) continue;
      copied = frame;
      const size_t at = static_cast<size_t>(layer);
      l.copied_call[at] = call;
      const bool from_lead = lead && lead->copied_frame[at] == frame && lead->copied_call[at] < call;
      g.BindFramebuffer(GL_READ_FRAMEBUFFER, layer_fbo[0]);
      attach_texture_layer(GL_READ_FRAMEBUFFER, point, im.kind, from_lead ? lead->texture : im.app, layer);
      g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, layer_fbo[1]);
      attach_texture_layer(GL_DRAW_FRAMEBUFFER, point, im.kind, l.texture, layer);
      if (color) {
        g.ReadBuffer(GL_COLOR_ATTACHMENT0);
        pgl().DrawBuffers(1, &point);
      }
      g.BlitFramebuffer(0, 0, from_lead ? lead->width : src_w, from_lead ? lead->height : src_h, 0, 0, dst_w, dst_h,
                        mask, GL_NEAREST);
    }
  }

  // `whole`: every image; else only layers of layered images not yet copied this frame (the
  // framebuffer was described again after the app re-attached its images).
  void copy_in(Stream& st, GLuint app, Shadow& s, bool whole) {
    const ApplyGl& g = agl();
    const ProbeGl& p = pgl();
    const GLuint real = targets()->real_framebuffer(app);
    double sx = 1.0, sy = 1.0;
    targets()->stored_scale(app, &sx, &sy);
    const int app_w = static_cast<int>(s.app_width * sx + 0.5), app_h = static_cast<int>(s.app_height * sy + 0.5);
    // A stream that forked from stream 0 starts from stream 0's image where it has one.
    const Shadow* lead = lead_shadow(st, app);
    const GLuint from = lead ? lead->fbo : real;
    const int src_w = lead ? lead->width : app_w, src_h = lead ? lead->height : app_h;
    // Multisampled images are blitted only at their own size: a shadow of another scale starts
    // undefined, as the window's content does after a swap (apps clear it first).
    bool multisampled = false;
    for (const ShadowImage& im : s.images) multisampled |= im.samples > 0;
    if (multisampled && (src_w != s.width || src_h != s.height)) return;
    for (const ShadowImage& im : s.images)
      if (im.layered()) copy_layers(st, im, app_w, app_h, s.width, s.height);
    g.BindFramebuffer(GL_READ_FRAMEBUFFER, from);
    g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, s.fbo);
    const GLint read_buffer = get(GL_READ_BUFFER);
    GLbitfield depth_stencil = 0;
    for (const ShadowImage& im : s.images) {
      if (im.layered() || !whole || overwritten(im.point)) continue;
      if (im.point == GL_DEPTH_ATTACHMENT)
        depth_stencil |= GL_DEPTH_BUFFER_BIT;
      else if (im.point == GL_STENCIL_ATTACHMENT)
        depth_stencil |= GL_STENCIL_BUFFER_BIT;
      else if (im.point == GL_DEPTH_STENCIL_ATTACHMENT)
        depth_stencil |= GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT;
      else {
        const GLenum source = !lead && app == 0 && !targets()->window_scaled() ? GL_BACK : im.point;
        g.ReadBuffer(source);
        const GLenum target = im.point;
        p.DrawBuffers(1, &target);
        g.BlitFramebuffer(0, 0, src_w, src_h, 0, 0, s.width, s.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
      }
    }
    // The window without a depth buffer of its own leaves the shadow's undefined: cleared
    // by the app, as it clears the window.
    if (depth_stencil && (lead || !(app == 0 && !targets()->window_scaled() && !window_has_depth())))
      g.BlitFramebuffer(0, 0, src_w, src_h, 0, 0, s.width, s.height, depth_stencil, GL_NEAREST);
    g.ReadBuffer(static_cast<GLenum>(read_buffer));
    // The app's draw buffers again (the copy set one at a time).
    GLenum draw_buffers[kMaxColorAttachments];
    GLsizei count = 0;
    if (app == 0) {
      draw_buffers[count++] = GL_COLOR_ATTACHMENT0;
    } else {
      g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, real);
      for (int i = 0; i < kMaxColorAttachments; ++i)
        draw_buffers[count++] = static_cast<GLenum>(get(GL_DRAW_BUFFER0 + i));
      g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, s.fbo);
    }
    p.DrawBuffers(count, draw_buffers);
  }

  // The real window's depth and stencil as an attachment point and a sized format; a window
  // with neither gets GL_DEPTH24_STENCIL8 (nothing is copied into it: the app clears it).
  std::pair<GLenum, GLint> window_depth_stencil() {
    const TargetScaler::DepthStencil& w = targets()->window_depth_stencil();
    if (w.depth_bits <= 0 && w.stencil_bits > 0) return {GL_STENCIL_ATTACHMENT, GL_STENCIL_INDEX8};
    const GLint format = w.depth_bits > 0 ? sized_depth_format(w.depth_bits, w.stencil_bits, w.floating_depth) : 0;
    if (!format) return {GL_DEPTH_STENCIL_ATTACHMENT, GL_DEPTH24_STENCIL8};
    return {w.stencil_bits > 0 ? GL_DEPTH_STENCIL_ATTACHMENT : GL_DEPTH_ATTACHMENT, format};
  }

  bool window_has_depth() { return targets()->window_depth_stencil().depth_bits > 0; }

  // The stream's shadow of the app's framebuffer, made and filled for this frame if needed.
  // The caller saved the draw and read bindings; both may change.
  // Whether the stream's shadow of the app's framebuffer is filled for this frame and still
  // attached as the app's framebuffer is.
  bool current(const Shadow& s) const {
    return s.initialized_frame == frame && s.described_changes == targets()->attachment_changes();
  }

  Shadow* shadow(Stream& st, GLuint app) {
    auto [it, fresh] = st.shadows.try_emplace(app);
    Shadow& s = it->second;
    if (current(s)) return s.usable ? &s : nullptr;
    // Described already this frame, before the app attached other images (or layers) to some
    // framebuffer: what it drew into the shadow's images this frame is kept where they stay.
    const bool again = s.initialized_frame == frame;
    // The app's framebuffer must be bound for drawing to be described.
    agl().BindFramebuffer(GL_DRAW_FRAMEBUFFER, targets()->real_framebuffer(app));
    Shadow wanted;
    const bool ok = describe(app, targets()->scale_for(app, st.config), wanted);
    bool same = !fresh && ok && s.usable && wanted.width == s.width && wanted.height == s.height &&
                wanted.images.size() == s.images.size();
    for (size_t i = 0; same && i < wanted.images.size(); ++i) {
      const ShadowImage &a = wanted.images[i], &b = s.images[i];
      same = a.app == b.app && a.format == b.format && a.point == b.point && a.levels == b.levels &&
             a.samples == b.samples && a.kind == b.kind && a.layer == b.layer && a.layers == b.layers;
      // A layered shadow remade for another framebuffer of the stream (its scale changed).
      if (same && b.layered()) same = st.layered[b.app].texture == b.shadow;
    }
    if (!same) {
      release_shadow(s);
      if (ok) {
        s = wanted;
        build(st, s, app);
        agl().BindFramebuffer(GL_DRAW_FRAMEBUFFER, targets()->real_framebuffer(app));
      }
    }
    s.initialized_frame = frame;
    if (!again) s.filled_call = call;
    s.described_changes = targets()->attachment_changes();
    if (!ok) {
      st.complete = app != 0 && st.complete;  // the window matters; other targets: drawn as the app's
      return nullptr;
    }
    copy_in(st, app, s, !again || !same);
    for (const ShadowImage& im : s.images)
      if (!im.renderbuffer) st.textures[im.app] = {im.shadow, im.kind};
    return &s;
  }

  // Before the app's draw (`is_draw`), clear or blit into its bound framebuffer: every
  // stream that draws has its shadow of it holding the app's content from before the call
  // (or its lead's).
  void prepare(bool is_draw, GLbitfield clear_mask, int clear_draw_buffer) {
    const OwnGlWork own(c);  // errors the shadows' making raises are the shim's
    ++call;
    const GLuint app = app_draw_fbo();
    follow(app, is_draw);
    clearing = clear_mask ? cleared_whole(clear_mask, clear_draw_buffer) : 0;
    const GLint draw = get(GL_DRAW_FRAMEBUFFER_BINDING), read = get(GL_READ_FRAMEBUFFER_BINDING);
    bool touched = false;
    for (int s = 0; s < stream_count; ++s) {
      if (!streams[s].forked) continue;
      auto it = streams[s].shadows.find(app);
      if (it != streams[s].shadows.end() && current(it->second)) continue;
      shadow(streams[s], app);
      touched = true;
    }
    clearing = 0;
    if (touched) {
      agl().BindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(draw));
      agl().BindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(read));
    }
  }

  // The images of the bound framebuffer the clear about to be made overwrites whole, by
  // attachment point (bit i: colour attachment i; then depth, then stencil): a shadow made or
  // first used this frame for that clear need not start from the app's content there, a
  // shadow map's 2048² depth among them. `draw_buffer`: the one a glClearBuffer* clears (-1:
  // every draw buffer, glClear). None where the clear is confined (scissor, write masks,
  // rasterizer discard) or the streams will not repeat it.
  static constexpr uint32_t kDepthBit = 1u << kMaxColorAttachments, kStencilBit = kDepthBit << 1;
  uint32_t clearing = 0;
  uint32_t cleared_whole(GLbitfield mask, int draw_buffer) {
    const ApplyGl& g = agl();
    const ProbeGl& p = pgl();
    if (!p.GetBooleanv || g.IsEnabled(GL_SCISSOR_TEST) || !duplicate_allowed()) return 0;
    if (at_least(3, 0, 3, 0) && g.IsEnabled(GL_RASTERIZER_DISCARD)) return 0;
    uint32_t bits = 0;
    if (mask & GL_COLOR_BUFFER_BIT) {
      const int first = draw_buffer < 0 ? 0 : draw_buffer;
      const int last = draw_buffer < 0 ? kMaxColorAttachments - 1 : std::min(draw_buffer, kMaxColorAttachments - 1);
      for (int i = first; i <= last; ++i) {
        const GLint buffer = get(GL_DRAW_BUFFER0 + static_cast<GLenum>(i));
        int point = -1;
        if (buffer >= static_cast<GLint>(GL_COLOR_ATTACHMENT0) &&
            buffer < static_cast<GLint>(GL_COLOR_ATTACHMENT0) + kMaxColorAttachments)
          point = buffer - static_cast<GLint>(GL_COLOR_ATTACHMENT0);
        else if (buffer == GL_BACK || buffer == GL_BACK_LEFT)
          point = 0;  // the window's, whose shadow has it at colour attachment 0
        if (point < 0) continue;
        GLboolean rgba[4] = {GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE};
        if (p.GetBooleani_v && at_least(3, 0, 3, 0))
          p.GetBooleani_v(GL_COLOR_WRITEMASK, static_cast<GLuint>(i), rgba);
        else if (i == 0)
          p.GetBooleanv(GL_COLOR_WRITEMASK, rgba);
        if (rgba[0] && rgba[1] && rgba[2] && rgba[3]) bits |= 1u << point;
      }
    }
    if (mask & GL_DEPTH_BUFFER_BIT) {
      GLboolean depth = GL_FALSE;
      p.GetBooleanv(GL_DEPTH_WRITEMASK, &depth);
      if (depth) bits |= kDepthBit;
    }
    if ((mask & GL_STENCIL_BUFFER_BIT) && (get(GL_STENCIL_WRITEMASK) & 0xff) == 0xff) bits |= kStencilBit;
    return bits;
  }
  bool overwritten(GLenum point) const {
    if (point == GL_DEPTH_ATTACHMENT) return clearing & kDepthBit;
    if (point == GL_STENCIL_ATTACHMENT) return clearing & kStencilBit;
    if (point == GL_DEPTH_STENCIL_ATTACHMENT)
      return (clearing & (kDepthBit | kStencilBit)) == (kDepthBit | kStencilBit);
    const GLenum i = point - GL_COLOR_ATTACHMENT0;
    return i < static_cast<GLenum>(kMaxColorAttachments) && ((clearing >> i) & 1);
  }

  // Whether the call about to be made into the app's framebuffer `fbo` (`draw`: by the bound
  // program; else a clear or blit, which no program takes part in) draws the same at `config`
  // as at `other`: the same level of the program's pass, and the framebuffer at the same scale
  // (`other_is_app`: as the app's images are stored now). What it samples was drawn by earlier
  // calls, the same in both while they follow. A pipeline's stages may belong to several
  // passes: the same only where the configurations are.
  bool same_call(const Levels& config, const Levels& other, GLuint fbo, bool draw, bool other_is_app) const {
    if (draw) {
      if (c.pipeline && !c.program) {
        if (!(config == other)) return false;
      } else if (c.manifest_pass >= 0 && config[c.manifest_pass] != other[c.manifest_pass]) {
        return false;
      }
    }
    const double scale = targets()->scale_for(fbo, config);
    return other_is_app ? targets()->stored_at(fbo, scale) : scale == targets()->scale_for(fbo, other);
  }

  // Before a call into the app's framebuffer `fbo`: each stream that still follows and would
  // draw this call differently forks. Stream 0 first: a stream that follows it forks at the
  // latest where it does.
  void follow(GLuint fbo, bool draw) {
    for (int s = 0; s < stream_count; ++s) {
      Stream& st = streams[s];
      if (st.forked) continue;
      const bool app = st.follows_app && same_call(st.config, c.config, fbo, draw, true);
      const bool first = st.follows_first && same_call(st.config, streams[0].config, fbo, draw, false);
      if (app || first) {
        st.follows_app = app;
        st.follows_first = first;
        continue;
      }
      st.forked = true;
      st.fork_call = call;
      st.lead = st.follows_app ? -1 : 0;
      // What stream 0 drew so far is what this one would have: its draws sample it.
      if (st.lead == 0) st.textures = streams[0].textures;
    }
  }

  // The stream's lead's shadow of the app's framebuffer `app`, filled before the call being
  // made, or null: its lead is the app, or drew into it as the app's, or filled it from the
  // app's for this very call (the stream fills its own from the app's too, not through the
  // lead's other scale).
  const Shadow* lead_shadow(const Stream& st, GLuint app) const {
    if (st.lead != 0) return nullptr;
    const Shadow* lead = filled(streams[0], app);
    return lead && lead->filled_call < call ? lead : nullptr;
  }

  // The stream's shadow of the app's framebuffer `app` where it is usable and filled this
  // frame, else null.
  const Shadow* filled(const Stream& st, GLuint app) const {
    const auto it = st.shadows.find(app);
    return it != st.shadows.end() && it->second.usable && it->second.initialized_frame == frame ? &it->second : nullptr;
  }

  // A program whose draws write buffers or count atomically: a duplicate would write twice.
  std::unordered_map<GLuint, bool> side_effects;
  bool has_side_effects(GLuint program) {
    if (!program) return false;
    auto it = side_effects.find(program);
    if (it != side_effects.end()) return it->second;
    const ApplyGl& g = agl();
    GLint blocks = 0, atomics = 0;
    if (g.GetProgramInterfaceiv &&
        (c.caps.gles ? c.caps.major * 10 + c.caps.minor >= 31 : c.caps.major * 10 + c.caps.minor >= 43))
      g.GetProgramInterfaceiv(program, GL_SHADER_STORAGE_BLOCK, GL_ACTIVE_RESOURCES, &blocks);
    if (c.caps.gles ? c.caps.major * 10 + c.caps.minor >= 31 : c.caps.major * 10 + c.caps.minor >= 42)
      g.GetProgramiv(program, GL_ACTIVE_ATOMIC_COUNTER_BUFFERS, &atomics);
    return side_effects[program] = blocks > 0 || atomics > 0;
  }

  bool duplicate_allowed() {
    if (c.list_compile_only) return false;
    if (has_side_effects(c.real_program)) return false;
    // Each query only where the context knows the enum (an error would reach the app).
    if (at_least(4, 0, 3, 0) && get(GL_TRANSFORM_FEEDBACK_ACTIVE)) return false;
    if (pgl().GetQueryiv) {
      const struct {
        GLenum target;
        bool known;
      } queries[] = {{GL_SAMPLES_PASSED, !c.caps.gles},
                     {GL_ANY_SAMPLES_PASSED, at_least(3, 3, 3, 0)},
                     {GL_ANY_SAMPLES_PASSED_CONSERVATIVE, at_least(4, 3, 3, 0)}};
      for (const auto& q : queries) {
        if (!q.known) continue;
        GLint current = 0;
        pgl().GetQueryiv(q.target, GL_CURRENT_QUERY, &current);
        if (current) return false;
      }
    }
    return true;
  }

  bool set_up(int s) {
    Stream& st = streams[s];
    if (!st.complete || !st.forked) return false;
    const Shadow* own = filled(st, app_draw_fbo());
    if (!own) return false;
    const Shadow& sh = *own;
    // The stream's variant of the app's program (its draws may be skipped at its level).
    c.config = st.config;
    // A level that skips its pass's draws skips no clear: the app's own clears are made.
    if (c.bound_variants) {
      bind_program(c);
      if (!duplicating_clear && !c.bound_variants->at(st.config).draws) return false;
    } else if (c.pipeline && !c.program) {
      bind_pipeline_stages(c);
      if (!duplicating_clear && pipeline_skips(c)) return false;
    }
    const ApplyGl& g = agl();
    g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, sh.fbo);
    const double sx = static_cast<double>(sh.width) / sh.app_width, sy = static_cast<double>(sh.height) / sh.app_height;
    const GLint* v = targets()->app_viewport();
    const GLint* b = targets()->app_scissor();
    GLint viewport[4], scissor[4];
    scale_box(v, sx, sy, viewport);  // as the app's own scaled targets get them
    scale_box(b, sx, sy, scissor);
    g.Viewport(viewport[0], viewport[1], viewport[2], viewport[3]);
    g.Scissor(scissor[0], scissor[1], scissor[2], scissor[3]);
    for (int u = 0; u < units; ++u)
      for (int k = 0; k < kKindCount; ++k) {
        if (!((kinds >> k) & 1)) continue;
        auto t = st.textures.find(static_cast<GLuint>(unit_texture[u][k]));
        const bool want = t != st.textures.end() && t->second.kind == kKinds[k];
        if (!want && !redirected[u][k]) continue;
        agl().ActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(u));
        g.BindTexture(kKinds[k], want ? t->second.texture : static_cast<GLuint>(unit_texture[u][k]));
        redirected[u][k] = want;
      }
    if (c.bound_variants)
      give_app_space_for_stream(c.bound_variants->at(st.config), sh);
    else if (c.pipeline_fragment_variants)
      give_app_space_for_stream(c.pipeline_fragment_variants->at(st.config), sh);
    return true;
  }

  // A program in app coordinates (apply/app_space_uniforms.hpp) sees the app's pixels in the
  // stream's shadows, which hold the app's images at the stream's scales.
  void give_app_space_for_stream(const Variant& v, const Shadow& sh) {
    if (!v.program || !v.app_space.any()) return;
    const float rx = static_cast<float>(sh.app_width) / static_cast<float>(sh.width);
    const float ry = static_cast<float>(sh.app_height) / static_cast<float>(sh.height);
    give_app_space(v, rx, ry, [&](GLint unit) -> SamplerSize {
      const bool tracked = unit >= 0 && unit < units;
      const GLuint app = tracked ? static_cast<GLuint>(unit_texture[unit][0]) : targets()->texture_at_unit(unit);
      GLint w = 0, h = 0;
      bool scaled = false;
      if (!targets()->app_texture_size(app, &w, &h, &scaled)) return {0, 0, 0};
      return scaled || (tracked && redirected[unit][0]) ? SamplerSize{w, h, 1} : SamplerSize{0, 0, 0};
    });
  }

  bool begin_duplicate() {
    if (!frame) return false;
    // The app's errors, its draw's among them, are kept for it; what the duplicates raise is
    // read away in end_duplicate().
    keep_app_errors(c);
    if (!duplicate_allowed()) return false;
    // The pass draws in the scene, whatever the streams' levels do with this draw (the app's
    // own level may skip it too).
    if (c.manifest_pass >= 0 && c.manifest_pass < 64) passes_now |= uint64_t{1} << c.manifest_pass;
    saved_draw_fbo = get(GL_DRAW_FRAMEBUFFER_BINDING);
    agl().GetIntegerv(GL_VIEWPORT, saved_viewport);
    agl().GetIntegerv(GL_SCISSOR_BOX, saved_scissor);
    saved_active = get(GL_ACTIVE_TEXTURE);
    saved_config = c.config;
    kinds = 1;
    for (int s = 0; s < stream_count; ++s)
      for (const auto& [app, stand_in] : streams[s].textures) kinds |= 1u << kind_index(stand_in.kind);
    for (int u = 0; u < units; ++u) {
      agl().ActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(u));
      for (int k = 0; k < kKindCount; ++k) {
        if (!((kinds >> k) & 1)) continue;
        unit_texture[u][k] = get(TargetScaler::binding_of(kKinds[k]));
        redirected[u][k] = false;
      }
    }
    stream = -1;
    return true;
  }

  bool advance() {
    while (++stream < stream_count)
      if (set_up(stream)) return true;
    return false;
  }

  void end_duplicate() {
    const ApplyGl& g = agl();
    for (int u = 0; u < units; ++u)
      for (int k = 0; k < kKindCount; ++k) {
        if (!redirected[u][k]) continue;
        agl().ActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(u));
        g.BindTexture(kKinds[k], static_cast<GLuint>(unit_texture[u][k]));
        redirected[u][k] = false;
      }
    agl().ActiveTexture(static_cast<GLenum>(saved_active));
    c.config = saved_config;
    if (c.bound_variants)
      bind_program(c);
    else if (c.pipeline && !c.program)
      bind_pipeline_stages(c);
    g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(saved_draw_fbo));
    g.Viewport(saved_viewport[0], saved_viewport[1], saved_viewport[2], saved_viewport[3]);
    g.Scissor(saved_scissor[0], saved_scissor[1], saved_scissor[2], saved_scissor[3]);
    stream = -1;
    drain_gl_errors();
  }

  // --- The swap ---------------------------------------------------------------------------

  // The first `count` capture targets at this size, made as a probe frame first needs them:
  // three window-sized images where probes take one pass a frame, up to nine for sweeps.
  void ensure_captures(int width, int height, int count) {
    const ApplyGl& g = agl();
    if (capture_width != width || capture_height != height) {
      for (int i = 0; i < capture_count; ++i) {
        g.DeleteFramebuffers(1, &capture_fbo[i]);
        g.DeleteTextures(1, &capture_texture[i]);
        capture_fbo[i] = capture_texture[i] = 0;
      }
      capture_count = 0;
    }
    if (capture_count >= count) return;
    const GLint active = get(GL_ACTIVE_TEXTURE);
    agl().ActiveTexture(GL_TEXTURE0);
    const GLint texture = get(GL_TEXTURE_BINDING_2D);
    for (int i = capture_count; i < count; ++i) {
      g.GenFramebuffers(1, &capture_fbo[i]);
      g.GenTextures(1, &capture_texture[i]);
      g.BindTexture(GL_TEXTURE_2D, capture_texture[i]);
      pgl().TexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, width, height);
      g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, capture_fbo[i]);
      g.FramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, capture_texture[i], 0);
    }
    g.BindTexture(GL_TEXTURE_2D, static_cast<GLuint>(texture));
    agl().ActiveTexture(static_cast<GLenum>(active));
    capture_width = width;
    capture_height = height;
    capture_count = count;
  }

  // A single-sampled image for a multisampled window shadow's resolve.
  GLuint resolve_fbo = 0, resolve_color = 0;
  int resolve_width = 0, resolve_height = 0;
  void ensure_resolve(int width, int height) {
    const ApplyGl& g = agl();
    if (resolve_fbo && resolve_width == width && resolve_height == height) return;
    if (!resolve_fbo) {
      g.GenFramebuffers(1, &resolve_fbo);
      g.GenRenderbuffers(1, &resolve_color);
    }
    const GLint renderbuffer = get(GL_RENDERBUFFER_BINDING);
    g.BindRenderbuffer(GL_RENDERBUFFER, resolve_color);
    g.RenderbufferStorageMultisample(GL_RENDERBUFFER, 0, GL_RGBA8, width, height);
    g.BindRenderbuffer(GL_RENDERBUFFER, static_cast<GLuint>(renderbuffer));
    g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_fbo);
    g.FramebufferRenderbuffer(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, resolve_color);
    resolve_width = width;
    resolve_height = height;
  }

  struct SavedFramebuffers {
    GLint draw = get(GL_DRAW_FRAMEBUFFER_BINDING), read = get(GL_READ_FRAMEBUFFER_BINDING);
    GLint read_buffer = get(GL_READ_BUFFER);
    GLboolean scissor = agl().IsEnabled(GL_SCISSOR_TEST);
    ~SavedFramebuffers() {
      const ApplyGl& g = agl();
      g.BindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(read));
      g.ReadBuffer(static_cast<GLenum>(read_buffer));
      g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(draw));
      if (scissor) g.Enable(GL_SCISSOR_TEST);
    }
  };

  void before_present() {
    if (!frame) return;
    std::fill(std::begin(captured), std::end(captured), false);
    const OwnGlWork own(c);
    TargetScaler& t = *targets();
    const int w = t.window_width(), h = t.window_height();
    if (w <= 0 || h <= 0) return;
    SavedFramebuffers saved;
    const ApplyGl& g = agl();
    g.Disable(GL_SCISSOR_TEST);
    ensure_captures(w, h, stream_count + 1);
    for (int s = 0; s < stream_count; ++s) {
      captured[s + 1] = false;
      const Shadow* window = filled(streams[s], 0);
      if (!streams[s].complete || !streams[s].forked || !window) continue;
      GLuint from = window->fbo;
      if (window->images[0].samples > 0 && (window->width != w || window->height != h)) {
        // A multisampled shadow is resolved at its own size before it is stretched.
        ensure_resolve(window->width, window->height);
        g.BindFramebuffer(GL_READ_FRAMEBUFFER, from);
        g.ReadBuffer(GL_COLOR_ATTACHMENT0);
        g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_fbo);
        g.BlitFramebuffer(0, 0, window->width, window->height, 0, 0, window->width, window->height, GL_COLOR_BUFFER_BIT,
                          GL_NEAREST);
        from = resolve_fbo;
      }
      g.BindFramebuffer(GL_READ_FRAMEBUFFER, from);
      g.ReadBuffer(GL_COLOR_ATTACHMENT0);
      g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, capture_fbo[s + 1]);
      g.BlitFramebuffer(0, 0, window->width, window->height, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_LINEAR);
      captured[s + 1] = true;
    }
    for (int s = 1; s < stream_count; ++s)
      if (!captured[s + 1] && streams[s].complete && image_lead(s) == 0) copy_capture(1, s + 1);
  }

  // Whose window image a stream that drew none of its own has (it never forked, or forked
  // after the last call into the window): -1 the app's, 0 stream 0's. Where stream 0 drew
  // none either, the app's.
  int image_lead(int s) const {
    const Stream& st = streams[s];
    const int lead = st.forked ? st.lead : st.follows_app ? -1 : 0;
    return lead == 0 && s > 0 && captured[1] ? 0 : -1;
  }

  void copy_capture(int from, int to) {
    const ApplyGl& g = agl();
    g.BindFramebuffer(GL_READ_FRAMEBUFFER, capture_fbo[from]);
    g.ReadBuffer(GL_COLOR_ATTACHMENT0);
    g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, capture_fbo[to]);
    g.BlitFramebuffer(0, 0, capture_width, capture_height, 0, 0, capture_width, capture_height, GL_COLOR_BUFFER_BIT,
                      GL_NEAREST);
    captured[to] = true;
  }

  void after_present() {
    if (!frame) return;
    const OwnGlWork own(c);
    const ApplyGl& g = agl();
    const int w = capture_width, h = capture_height;
    // before_present made a capture target for each stream, unless the window had no size.
    if (w <= 0 || h <= 0 || capture_count < stream_count + 1) return end_frame();
    {
      SavedFramebuffers saved;
      g.Disable(GL_SCISSOR_TEST);
      g.BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
      g.ReadBuffer(GL_BACK);
      g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, capture_fbo[0]);
      g.BlitFramebuffer(0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
      captured[0] = true;
      for (int s = 0; s < stream_count; ++s)
        if (!captured[s + 1] && streams[s].complete && image_lead(s) == -1) copy_capture(0, s + 1);

      Readback r;
      r.capture.frame = frame;
      r.capture.context = c.index;
      r.capture.width = w;
      r.capture.height = h;
      r.capture.shown = saved_config_for_frame;
      r.capture.passes_drawn = passes_now | passes_drawn;
      bool all = true;
      for (int s = 0; s < stream_count; ++s) all = all && captured[s + 1];
      // pending has room: after_swap plans a probe only then.
      if (all) {
        for (int s = 0; s < stream_count; ++s) r.capture.streams.push_back(streams[s].config);
        if (!compare_on_gpu(r) || !probe_settings().dump_dir.empty()) read_back(r);
        pending.push_back(std::move(r));
      }
    }
    end_frame();
  }

  // The context's GpuSsim, made the first time (null: compared on the CPU).
  GpuSsim* gpu_ssim() {
    if (!gpu_made) {
      gpu_made = true;
      gpu = make_probe_ssim();
    }
    return gpu.get();
  }

  // After the GPU SSIM failed (std::exception from GpuSsim): the CPU from now on.
  void gpu_failed(const char* why) {
    say_once("probe-ssim-failed",
             std::string("the GPU SSIM failed (") + why + "); probe frames are compared on the CPU from now on");
    gpu.reset();
  }

  // Queues the probe frame's comparisons (the shown image and each stream's against s0's)
  // in the context's compute shaders; false where they are compared on the CPU.
  bool compare_on_gpu(Readback& r) {
    GpuSsim* ssim = gpu_ssim();
    if (!ssim) return false;
    const int w = r.capture.width, h = r.capture.height;
    const int scale = probe_ssim_scale(w, h);
    const size_t best = best_image(r.capture);
    try {
      for (size_t i = 0; i <= r.capture.streams.size(); ++i) {
        if (i == best) continue;
        const uint64_t ticket = ssim->submit(capture_texture[best], capture_texture[i], w, h, scale);
        r.comparisons.push_back({best, i, ticket});
      }
    } catch (const std::exception& e) {
      gpu_failed(e.what());
      r.comparisons.clear();
      return false;
    }
    return true;
  }

  // Starts reading the capture's images back into pixel-pack buffers, behind a fence (the
  // caller restores the read framebuffer).
  void read_back(Readback& r) {
    const ProbeGl& p = pgl();
    const ApplyGl& g = agl();
    const int w = r.capture.width, h = r.capture.height;
    const GLint pack = get(GL_PIXEL_PACK_BUFFER_BINDING), alignment = get(GL_PACK_ALIGNMENT);
    const GLint row_length = c.caps.gles && c.caps.major < 3 ? 0 : get(GL_PACK_ROW_LENGTH);
    p.PixelStorei(GL_PACK_ALIGNMENT, 4);
    if (row_length) p.PixelStorei(GL_PACK_ROW_LENGTH, 0);
    for (size_t i = 0; i <= r.capture.streams.size(); ++i) {
      GLuint buffer = 0;
      p.GenBuffers(1, &buffer);
      p.BindBuffer(GL_PIXEL_PACK_BUFFER, buffer);
      p.BufferData(GL_PIXEL_PACK_BUFFER, static_cast<GLsizeiptr>(w) * h * 4, nullptr, GL_STREAM_READ);
      g.BindFramebuffer(GL_READ_FRAMEBUFFER, capture_fbo[i]);
      g.ReadBuffer(GL_COLOR_ATTACHMENT0);
      p.ReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
      r.buffers.push_back(buffer);
    }
    r.fence = p.FenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    p.BindBuffer(GL_PIXEL_PACK_BUFFER, static_cast<GLuint>(pack));
    p.PixelStorei(GL_PACK_ALIGNMENT, alignment);
    if (row_length) p.PixelStorei(GL_PACK_ROW_LENGTH, row_length);
  }

  Levels saved_config_for_frame;

  void end_frame() {
    if (!retired_textures.empty()) {
      agl().DeleteTextures(static_cast<GLsizei>(retired_textures.size()), retired_textures.data());
      retired_textures.clear();
    }
    // A pass that left the scene is probed again when it comes back (its error then is not
    // the one it had).
    const manifest::Manifest& m = active_manifest();
    for (size_t i = 0; i < m.passes.size() && i < 64; ++i)
      if (!pass_in_scene(m.passes[i], i, passes_now)) passes_probed &= ~(uint64_t{1} << i);
    passes_drawn = passes_now;
    frame = 0;
    t_probe = nullptr;
  }

  // wait: the context goes away (destroyed, or the process exits) and these are its last
  // probe frames; a bounded wait for read-backs, so a hung driver cannot hold the app's exit.
  void collect(bool wait) {
    if (pending.empty()) return;
    const OwnGlWork own(c);
    while (!pending.empty()) {
      Readback& r = pending.front();
      if (!compared(r, wait) || !read(r, wait)) return;
      if (!probe_settings().dump_dir.empty()) dump(r.capture);
      // Nothing to compare where the GPU SSIM failed on a frame that was not read back.
      if (!r.capture.errors.empty() || !r.capture.images.empty()) governor_probe(std::move(r.capture));
      pending.erase(pending.begin());
    }
  }

  // The frame's GPU comparisons are all done (their errors in the capture), or there are none.
  bool compared(Readback& r, bool wait) {
    if (r.comparisons.empty()) return true;
    if (!gpu) {  // failed since
      r.comparisons.clear();
      return true;
    }
    try {
      std::vector<ProbeCapture::Compared> errors;
      for (const GpuComparison& k : r.comparisons) {
        const std::optional<double> ssim = wait ? gpu->wait(k.ticket) : gpu->poll(k.ticket);
        if (!ssim) return false;
        errors.push_back({k.a, k.b, 1.0 - *ssim});
      }
      r.capture.errors = std::move(errors);
    } catch (const std::exception& e) {
      gpu_failed(e.what());
    }
    r.comparisons.clear();
    return true;
  }

  // The frame's images are read back into the capture, or it has none to read.
  bool read(Readback& r, bool wait) {
    if (!r.fence) return true;
    const ProbeGl& p = pgl();
    constexpr GLuint64 kLastWaitNs = 2'000'000'000;
    const GLenum status = p.ClientWaitSync(r.fence, wait ? GL_SYNC_FLUSH_COMMANDS_BIT : 0, wait ? kLastWaitNs : 0);
    if (status != GL_ALREADY_SIGNALED && status != GL_CONDITION_SATISFIED) return false;
    p.DeleteSync(r.fence);
    r.fence = nullptr;
    const GLint pack = get(GL_PIXEL_PACK_BUFFER_BINDING);
    const size_t bytes = static_cast<size_t>(r.capture.width) * r.capture.height * 4;
    for (GLuint buffer : r.buffers) {
      p.BindBuffer(GL_PIXEL_PACK_BUFFER, buffer);
      const void* data = p.MapBufferRange(GL_PIXEL_PACK_BUFFER, 0, static_cast<GLsizeiptr>(bytes), GL_MAP_READ_BIT);
      std::vector<uint8_t> image(bytes);
      if (data) std::memcpy(image.data(), data, bytes);
      p.UnmapBuffer(GL_PIXEL_PACK_BUFFER);
      r.capture.images.push_back(std::move(image));
    }
    p.BindBuffer(GL_PIXEL_PACK_BUFFER, static_cast<GLuint>(pack));
    p.DeleteBuffers(static_cast<GLsizei>(r.buffers.size()), r.buffers.data());
    r.buffers.clear();
    return true;
  }

  static void dump(const ProbeCapture& capture) {
    for (size_t i = 0; i < capture.images.size(); ++i) {
      const std::string name = probe_settings().dump_dir + "/probe_c" + std::to_string(capture.context) + "_f" +
                               std::to_string(capture.frame) + "_" +
                               (i == 0 ? std::string("shown_") + format_levels(capture.shown)
                                       : "s" + std::to_string(i) + "_" + format_levels(capture.streams[i - 1])) +
                               ".ppm";
      std::FILE* f = std::fopen(name.c_str(), "wb");
      if (!f) {
        say_once("probe-dump", "cannot write probe images to " + probe_settings().dump_dir);
        return;
      }
      std::fprintf(f, "P6\n%d %d\n255\n", capture.width, capture.height);
      std::vector<uint8_t> row(static_cast<size_t>(capture.width) * 3);
      for (int y = capture.height - 1; y >= 0; --y) {  // GL rows are bottom-up
        const uint8_t* src = capture.images[i].data() + static_cast<size_t>(y) * capture.width * 4;
        for (int x = 0; x < capture.width; ++x)
          for (int k = 0; k < 3; ++k) row[static_cast<size_t>(x) * 3 + k] = src[x * 4 + k];
        std::fwrite(row.data(), 1, row.size(), f);
      }
      std::fclose(f);
    }
  }

  // The (pass, level) pairs probes take, in order, each given to `f` with its index: each pass at
  // its cheapest level, or at every level below the best (GLBUDGET_PROBE_LEVELS=all).
  template <class F>
  static void each_probe_pair(const manifest::Manifest& m, F&& f) {
    size_t k = 0;
    for (size_t i = 0; i < m.passes.size() && i < static_cast<size_t>(kMaxPasses); ++i) {
      const int lmax = static_cast<int>(m.passes[i].levels.size()) - 1;
      for (int l = options().probe_every_level ? 1 : lmax; l <= lmax && l >= 1; ++l) f(k++, i, l);
    }
  }
  static std::vector<std::pair<size_t, int>> probe_pairs(const manifest::Manifest& m) {
    std::vector<std::pair<size_t, int>> order;
    each_probe_pair(m, [&](size_t, size_t i, int level) { order.emplace_back(i, level); });
    return order;
  }
  // The pairs of passes in the scene last probed before `frame` (never probed included). Asked
  // after each swap in rounds: it allocates nothing.
  int pairs_probed_before(uint64_t frame) const {
    const manifest::Manifest& m = active_manifest();
    int stale = 0;
    each_probe_pair(m, [&](size_t k, size_t i, int) {
      if (pass_in_scene(m.passes[i], i, passes_drawn) && (k >= pair_probed.size() || pair_probed[k] < frame)) ++stale;
    });
    return stale;
  }

  // The streams of a probe frame: s0, unless the frame is drawn in it, and s_i^lmax for a pass
  // that has levels and drew in the last probe frame: the next in turn (GLBUDGET_PROBE_ORDER=
  // weighted: until each has been probed, then the one whose error × age is largest; with
  // `stalest`, a round's, the one probed longest ago, or weighted the largest error × age), or
  // with `sweep` every such pass, those probed longest ago first (weighted in a round: by error ×
  // age) where they are more than the streams (max_streams, s0 counted whether it is drawn or
  // shown).
  void plan(uint64_t next, bool sweep, int max_streams = kMaxStreams, bool stalest = false) {
    const manifest::Manifest& m = active_manifest();
    const int passes = std::min<int>(static_cast<int>(m.passes.size()), kMaxPasses);
    stream_count = 0;
    Levels best;
    best.count = passes;
    if (!(c.config == best)) streams[stream_count++].config = best;
    const std::vector<std::pair<size_t, int>> order = probe_pairs(m);
    const auto probeable = [&](size_t i) {
      return i < static_cast<size_t>(kMaxPasses) && pass_in_scene(m.passes[i], i, passes_drawn);
    };
    pair_probed.resize(order.size());
    // The stream of pair k (none where the frame is drawn in it: the shown image is its probe).
    const auto probe_pair = [&](size_t k) {
      const auto [i, level] = order[k];
      pair_probed[k] = next;
      Levels probed = best;
      probed.level[i] = static_cast<int8_t>(level);
      if (i < 64 && level + 1 == static_cast<int>(m.passes[i].levels.size())) passes_probed |= uint64_t{1} << i;
      if (!(probed == c.config)) streams[stream_count++].config = probed;
    };
    size_t pick = order.size();
    // The candidates of the weighted order: each pair's pass's latest error and its last probe.
    const auto weigh = [&] {
      candidates.resize(order.size());
      for (size_t k = 0; k < order.size(); ++k) {
        const size_t i = order[k].first;
        candidates[k] = {probeable(i) ? g_pass_error[i].load(std::memory_order_relaxed) : 0.0, pair_probed[k],
                         probeable(i)};
      }
    };
    if (stalest && options().probe_order_weighted) {
      // A round's probe frame, weighted: its passes by error × age, each taken once (a round ahead
      // of a selection may be cut short by one that comes early, and then what it had probed were
      // the passes whose staleness moves the ranking most).
      if (sweep) sweep_soon = false;
      weigh();
      // A pass probed longer ago than the whole age bound goes first, as one never probed: the
      // bound is what brought this probe frame (round_due).
      const uint64_t whole = age_bound_frames(probe_settings(), true);
      for (size_t k = 0; k < order.size(); ++k)
        if (whole && next > whole && pair_probed[k] < next - whole)
          candidates[k].error = std::numeric_limits<double>::quiet_NaN();
      for (int passes_left = sweep ? max_streams - 1 : 1; passes_left > 0 && stream_count < kMaxStreams;
           --passes_left) {
        const size_t k = loop::next_probe(candidates, next);
        if (k >= order.size()) break;
        candidates[k].in_scene = false;
        probe_pair(k);
      }
    } else if (sweep || stalest) {
      if (sweep) sweep_soon = false;
      std::vector<size_t> taken;
      for (size_t k = 0; k < order.size(); ++k)
        if (probeable(order[k].first)) taken.push_back(k);
      std::stable_sort(taken.begin(), taken.end(), [&](size_t a, size_t b) { return pair_probed[a] < pair_probed[b]; });
      // At most max_streams - 1 passes (s0 beside them, whether drawn or shown); the stalest alone
      // where the frame probes one pass.
      int passes_left = sweep ? max_streams - 1 : 1;
      for (size_t k : taken)
        if (stream_count < kMaxStreams && passes_left-- > 0) probe_pair(k);
    } else if (options().probe_order_weighted && settled()) {
      weigh();
      pick = loop::next_probe(candidates, next);
    } else {
      for (size_t tries = 0; tries < order.size() && pick == order.size(); ++tries) {
        const size_t k = next_pass++ % order.size();
        if (probeable(order[k].first)) pick = k;
      }
    }
    if (pick < order.size()) probe_pair(pick);
    // Slots only a sweep uses, unused by this probe frame: their shadows go (plan runs between
    // frames, so nothing draws from them). The two a probe of one pass uses are kept, as before
    // sweeps, across frames shown at s0 (one stream) and elsewhere (two).
    for (int s = std::max(stream_count, 2); s < kMaxStreams; ++s) release_stream(streams[s]);
    if (stream_count == 0) return;
    const bool follow = options().probe_follow;
    for (int s = 0; s < stream_count; ++s) {
      Stream& st = streams[s];
      st.textures.clear();
      st.complete = true;
      st.forked = !follow;
      st.follows_app = follow;
      st.follows_first = follow && s > 0;
      st.lead = -1;
      st.fork_call = 0;
    }
    call = 0;
    frame = next;
    recent_sweep_streams[recent_at % 16] = sweep ? stream_count : 0;
    recent[recent_at++ % 16] = next;
    passes_now = 0;
    saved_config_for_frame = c.config;
    units = std::min<int>(kMaxUnits, std::max<int>(1, get(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS)));
    t_probe = owner;
  }

  // Passes probed at their cheapest level so far; every pass with levels: settled.
  uint64_t passes_probed = 0;
  uint64_t drift_seen = 0;  // probe_drift_count() when last looked at
  uint64_t last_tried = 0;  // the frame a probe was last planned for (or tried: nothing to probe)
  bool settled() const {
    const manifest::Manifest& m = active_manifest();
    for (size_t i = 0; i < m.passes.size() && i < 64; ++i)
      if (m.passes[i].levels.size() > 1 && ((passes_drawn >> i) & 1) && !((passes_probed >> i) & 1)) return false;
    return true;
  }

  // Each pass in the scene probed again within GLBUDGET_PROBE_MAX_AGE_S: the most frames a
  // probe may wait after the last, that many seconds of this context's frames shared among those
  // passes (they are probed in turn), never fewer than the first period nor than one probe per
  // governor window (one_probe_per_window_gap); 0: no bound. The settled factor counts frames,
  // so at a low frame rate a pass's estimate grew stale for tens of seconds (Valley at 10 fps:
  // its passes' probes 130-160 frames old at the selections). The window's floor: a window's
  // margin holds one probe's excess, and six passes in 6 s at 10 fps, a probe every 10 frames
  // with a 3-frame span, put two into some windows (the demo's Hall at 50 %: 0.92 of its
  // windows kept). Not where the governor spaces bursts too: there every window holding a
  // probe is over the budget whatever is shown, and more probes would only put more windows over.
  // With `whole` (GLBUDGET_PROBE_SWEEP, every pass in one probe frame): the bound's frames
  // unshared.
  uint64_t age_bound_frames(const ProbeSettings& settings, bool whole = false) const {
    const double age_s = options().probe_max_age_s;
    if (!settings.stretchable || !(age_s > 0.0) || !(frame_s > 0.0) || g_bursts_spaced.load(std::memory_order_relaxed))
      return 0;
    const int in_scene = passes_in_scene();
    if (in_scene == 0) return 0;
    const double frames = age_s / frame_s / (whole ? 1 : in_scene);
    if (!(frames < 1e9)) return 0;
    return std::max(window_gap(settings), static_cast<uint64_t>(frames));
  }
  // The passes with levels that drew in the last probe frame (all before the first).
  int passes_in_scene() const {
    const manifest::Manifest& m = active_manifest();
    int in_scene = 0;
    for (size_t i = 0; i < m.passes.size() && i < static_cast<size_t>(kMaxPasses); ++i)
      if (m.passes[i].levels.size() > 1 && pass_in_scene(m.passes[i], i, passes_drawn)) ++in_scene;
    return in_scene;
  }
  // The fewest frames between probes: the first period, and one probe per governor window.
  uint64_t window_gap(const ProbeSettings& settings) const {
    return std::max(settings.period,
                    frame_s > 0.0 ? loop::one_probe_per_window_gap(loop::FeedbackSettings{}.window_s / frame_s) : 0);
  }
  // GLBUDGET_PROBE_SWEEP, once every pass in the scene is probed: a probe frame measures them
  // all, s0 drawn once for all of them, so that the governor's selection weighs errors of one
  // frame rather than passes probed in turn up to the age bound before it (on the demo's Valley at
  // 10 fps, four passes probed every 25 frames left base shading's error 84 frames old at a
  // selection, and the estimates ranked at 0.944 where that frame's own errors rank at 0.988).
  // A sweep comes kSweepLead frames ahead of each selection due by the governor's period
  // (a selection decides by the estimates of that moment, and a pass probed in turn up to the
  // bound before it is what Valley's ranking lacked), and at the longest gap anyway: the whole
  // age bound, or where that is longer or there is none, the settled period times
  // kSweepCostInProbes (a sweep costs about as much as that many probes of one pass each, so
  // that sweeps cost no more than the probes in turn did). After a pass's error moved, half the
  // longest gap after the last, unless a selection is due within that. Never two in one
  // window. Where the governor spaces probes (g_bursts_spaced: a window holding one is over the
  // budget whatever is shown), a sweep a longest gap (the settled period the governor asks for,
  // unscaled), drawn ahead of the selection due in the last selection period of it. With
  // GLBUDGET_PROBE_PERIOD given, a sweep every period.
  uint64_t longest_sweep_gap(const ProbeSettings& settings, uint64_t settled_period) const {
    if (!settings.stretchable) return settings.period;
    // Spaced, what a probe costs is a window over the budget, a sweep's one as a probe of one
    // pass's: the governor's period unscaled.
    if (g_bursts_spaced.load(std::memory_order_relaxed)) return std::max(window_gap(settings), settled_period);
    const uint64_t as_costly =
        settled_period * static_cast<uint64_t>(std::clamp(passes_in_scene(), 1, kSweepCostInProbes));
    const uint64_t whole = age_bound_frames(settings, true);
    return std::max(window_gap(settings), whole ? std::min(whole, as_costly) : as_costly);
  }
  // The shortest gap before a sweep after a pass's error moved.
  uint64_t early_sweep_gap(const ProbeSettings& settings, uint64_t settled_period) const {
    return std::max(window_gap(settings), longest_sweep_gap(settings, settled_period) / 2);
  }
  bool sweep_soon = false;  // a pass's error moved since the last sweep
  bool sweep_due(const ProbeSettings& settings, uint64_t settled_period, uint64_t next) const {
    const uint64_t since = next - last_tried;
    const uint64_t longest = longest_sweep_gap(settings, settled_period);
    if (!settings.stretchable) return next % longest == 0 && since >= longest;
    if (since < window_gap(settings)) return false;
    const uint64_t due = g_selection_due.load(std::memory_order_relaxed);
    const uint64_t to_due = due > next ? due - next : UINT64_MAX;
    // At the longest gap anyway, but not while the governor moves to what it just selected:
    // the configuration still shown was chosen with no room for a sweep where the governor
    // had spaced probes, and a sweep there put its window over the budget (the demo's Hall at
    // 40 %: sweeps at the longest gap two frames into a transition, each window over by 2-3 W).
    // A window's frames past the longest gap at most (which may be the age bound).
    if (since >= longest)
      return to_due <= kSweepLead || !g_transitioning.load(std::memory_order_relaxed) ||
             since >= longest + window_gap(settings);
    if (g_bursts_spaced.load(std::memory_order_relaxed)) {
      // The governor wants them rare: one a longest gap still, but ahead of the selection due
      // within the last selection period of that gap rather than at the gap itself.
      const uint64_t selections = g_select_frames.load(std::memory_order_relaxed);
      return to_due <= kSweepLead && since + selections >= longest;
    }
    if (to_due <= kSweepLead) return true;
    // A pass that moved waits for a selection due within the early gap: the sweep ahead of it
    // measures the same and keeps the sweeps where the selections are.
    const uint64_t early = early_sweep_gap(settings, settled_period);
    return sweep_soon && since >= early && to_due > early;
  }
  // The frames between sweeps on average, for the governor's probe overhead.
  uint64_t sweep_gap(const ProbeSettings& settings, uint64_t settled_period) const {
    const uint64_t longest = longest_sweep_gap(settings, settled_period);
    if (!settings.stretchable) return longest;
    const uint64_t selections = g_select_frames.load(std::memory_order_relaxed);
    const bool selection_known = selections && g_selection_due.load(std::memory_order_relaxed);
    if (g_bursts_spaced.load(std::memory_order_relaxed)) {
      // sweep_due's spaced case: the selection due a gap of at least longest - selections after
      // the last sweep, a whole number of selection periods (at least one), never past longest.
      if (!selection_known) return longest;
      const uint64_t periods = std::max<uint64_t>(1, (longest + selections - 1) / selections - 1);
      return std::clamp(periods * selections, window_gap(settings), longest);
    }
    const uint64_t early = early_sweep_gap(settings, settled_period);
    if (sweep_soon) return early;  // the scene moves: as often as that allows
    if (!selection_known) return longest;
    return std::min(longest, std::max(selections, window_gap(settings)));  // ahead of each selection
  }

  // Probes of one pass or a few at a time (the governor found no room under its budget for a
  // sweep's excess in a window: Governor::probe_streams_fit), where it selects at a known frame:
  // the passes in the scene, stalest first, in the windows just ahead of each selection, one probe
  // frame a window, the last kSweepLead frames ahead of it, so that the selection weighs errors a
  // few windows old, as a sweep's are, rather than anywhere up to the age bound (the demo's Valley
  // at 50 %, four passes in turn: 47-109 frames old at the last selection, the estimates ranking
  // the 729 configurations at ρ 0.943-0.950; a probe every window throughout: 20 frames, ρ 0.984,
  // at twice the probe frames). The frames of such a round: one per `passes_a_frame` passes in
  // the scene, as many as a selection period holds; 0 where the governor spaces probes (a window
  // holding one is over the budget whatever is shown), where no selection is due, or where the
  // user gave GLBUDGET_PROBE_PERIOD.
  int round_frames(const ProbeSettings& settings, int passes_a_frame) const {
    const uint64_t selections = g_select_frames.load(std::memory_order_relaxed);
    if (!settings.stretchable || selections <= kSweepLead || !g_selection_due.load(std::memory_order_relaxed) ||
        g_bursts_spaced.load(std::memory_order_relaxed))
      return 0;
    const int needed = (passes_in_scene() + passes_a_frame - 1) / std::max(1, passes_a_frame);
    const uint64_t fit = (selections - kSweepLead - 1) / window_gap(settings) + 1;
    return static_cast<int>(std::min<uint64_t>(static_cast<uint64_t>(std::max(needed, 0)), fit));
  }
  // A round's probe frame at `next`: the pairs not yet probed in the round that began `frames`
  // windows ahead of the selection due need that many frames still, the last kSweepLead ahead
  // of it; or a pass's probe older than the whole age bound (GLBUDGET_PROBE_MAX_AGE_S), where
  // selections are further apart than it.
  bool round_due(const ProbeSettings& settings, uint64_t next, int passes_a_frame, int frames) const {
    const uint64_t gap = window_gap(settings);
    if (next - last_tried < gap) return false;
    const uint64_t whole = age_bound_frames(settings, true);
    if (whole && next > whole && pairs_probed_before(next - whole) > 0) return true;
    const uint64_t due = g_selection_due.load(std::memory_order_relaxed);
    if (due <= next) return false;
    const uint64_t span = kSweepLead + static_cast<uint64_t>(frames - 1) * gap;
    if (due - next > span) return false;
    const int stale = pairs_probed_before(due > span ? due - span : 0);
    const int left = std::min(frames, (stale + passes_a_frame - 1) / std::max(1, passes_a_frame));
    return left > 0 && due - next <= kSweepLead + static_cast<uint64_t>(left - 1) * gap;
  }

  // This context's seconds between swaps, smoothed over about ten frames.
  void time_swap() {
    const auto now = std::chrono::steady_clock::now();
    if (last_swap != std::chrono::steady_clock::time_point{}) {
      const double dt = std::chrono::duration<double>(now - last_swap).count();
      frame_s = frame_s > 0.0 ? 0.9 * frame_s + 0.1 * dt : dt;
    }
    last_swap = now;
  }
  std::chrono::steady_clock::time_point last_swap{};
  double frame_s = 0.0;

  ProbeFrames* owner = nullptr;
  uint64_t recent[16] = {};
  int recent_sweep_streams[16] = {};  // of each recent probe frame: its streams where a sweep, else 0
  size_t recent_at = 0;
  // The slot of `frame` among the recent probe frames; -1 where it is not one.
  int recent_slot(uint64_t frame) const {
    for (int k = 0; k < 16; ++k)
      if (frame && recent[k] == frame) return k;
    return -1;
  }
};

ProbeFrames::ProbeFrames(ContextState& c) : impl_(std::make_unique<Impl>(c)) { impl_->owner = this; }
ProbeFrames::~ProbeFrames() {
  if (t_probe == this) t_probe = nullptr;
  // Its GL objects go with the context, which need not be current here.
  (void)impl_->gpu.release();
}

int probe_ssim_scale(int width, int height) {
  return options().probe_scale ? options().probe_scale : quality::wang_rule_scale(width, height);
}

bool pass_in_scene(const manifest::Pass& pass, size_t i, uint64_t passes_drawn) {
  return pass.scales_targets() || i >= 64 || ((passes_drawn >> i) & 1);
}

size_t best_image(const ProbeCapture& capture) {
  size_t best = 0;
  for (size_t s = 0; s < capture.streams.size(); ++s) {
    bool all_best = true;
    for (int i = 0; i < capture.streams[s].count; ++i) all_best = all_best && capture.streams[s].level[i] == 0;
    if (all_best) best = s + 1;
  }
  return best;
}

void ProbeFrames::before_present() { impl_->before_present(); }
void ProbeFrames::after_present() { impl_->after_present(); }

void ProbeFrames::abandon_frame() {
  Impl& p = *impl_;
  if (!p.frame) return;
  const ProbeGl& g = pgl();
  if (GLsync fence = g.FenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0)) {
    g.ClientWaitSync(fence, GL_SYNC_FLUSH_COMMANDS_BIT, 2'000'000'000);
    g.DeleteSync(fence);
  }
  p.end_frame();
}

void ProbeFrames::after_swap(uint64_t next) {
  Impl& p = *impl_;
  if (!p.probe_possible()) return;
  // Only the age bound and sweeps read the frame time.
  if (options().probe_max_age_s > 0.0 || options().probe_sweep) p.time_swap();
  p.collect(false);
  const ProbeSettings& settings = probe_settings();
  const uint64_t wanted = settings.stretchable ? g_period_wanted.load(std::memory_order_relaxed) : 0;
  const uint64_t settled_period = std::max(settings.period * settings.settled_factor, wanted);
  const uint64_t bound = settings.period ? p.age_bound_frames(settings) : 0;
  // Sweeps once every pass is probed, unless the governor has the passes probed in turn, several
  // at a time or one (a window holding a sweep would not fit under its budget). By default only
  // under a budget: sweeps are drawn ahead of the governor's selections, and where it does not
  // steer the passes go in turn at the user's period; GLBUDGET_PROBE_SWEEP=1 sweeps regardless.
  const bool sweepable = options().probe_sweep && (options().probe_sweep_set || governor_steering()) &&
                         !options().probe_every_level && settings.period;
  const int all_streams = std::min(kMaxStreams, p.passes_in_scene() + 1);
  // As many as the governor finds room for, and the user allows (s0 beside the passes).
  const int fit = g_streams_fit.load(std::memory_order_relaxed);
  const int allowed = options().probe_passes > 0 ? std::min(all_streams, options().probe_passes + 1) : all_streams;
  const int streams = fit > 0 ? std::min(fit, allowed) : allowed;
  const bool sweeping = sweepable && p.settled() && streams >= all_streams;
  const bool grouped = sweepable && p.settled() && !sweeping && streams > loop::kOnePassStreams;
  g_sweep_streams.store(sweeping || grouped ? streams : 0, std::memory_order_relaxed);
  g_sweepable_streams.store(sweepable ? allowed : 0, std::memory_order_relaxed);
  if (const uint64_t drift = probe_drift_count(); drift != p.drift_seen) {
    p.drift_seen = drift;
    // The scene moved: every pass's error again, at the first period. Not where the age bound
    // comes sooner than the settled period: it probes each pass within it anyway, and Valley
    // at 10 fps drew 51-54 probes in 600 frames where the bound alone gives about 22, so most
    // windows held one and the governor's margin for them showed cheaper configurations
    // (docs/evaluation/probes/probe-max-age.md).
    // Sweeping, one sweep measures every pass again, as soon as an early sweep may come.
    if (sweeping)
      p.sweep_soon = true;
    else if (!(bound && bound < settled_period))
      p.passes_probed = 0;
  }
  uint64_t period = settings.period;
  if (p.settled())
    period = settled_period;
  else if (g_bursts_spaced.load(std::memory_order_relaxed))
    period = std::max(period, wanted);
  // Probes of a pass or a few, settled, in rounds ahead of each selection where the governor steers.
  const int passes_a_frame = std::max(1, streams - 1);
  // Not where the governor asks for rarer probes and gets them; where the age bound comes sooner
  // than what it asks for, probes come at the bound anyway, and rounds place them.
  const bool rare_wanted = wanted && !(bound && bound < settled_period);
  const int round_frames =
      sweepable && p.settled() && !sweeping && !rare_wanted ? p.round_frames(settings, passes_a_frame) : 0;
  // The period the governor's probe overhead counts is the shorter of the two; in rounds, their
  // probe frames spread over the selection period.
  const uint64_t selections = g_select_frames.load(std::memory_order_relaxed);
  const uint64_t in_force = sweeping       ? p.sweep_gap(settings, settled_period)
                            : round_frames ? std::max(p.window_gap(settings), selections / round_frames)
                            : bound        ? std::min(period, bound)
                                           : period;
  if (in_force != g_period_in_force.load(std::memory_order_relaxed))
    g_period_in_force.store(in_force, std::memory_order_relaxed);
  // Not the first frames: the app may still be setting up what it draws. A period just made
  // longer also waits a whole period after the last probe tried; the age bound, counted from
  // the last probe tried, holds whatever frame number that falls on.
  if (period == 0 || next < 3) return;
  if (sweeping) {
    if (!p.sweep_due(settings, settled_period, next)) return;
  } else if (round_frames) {
    if (!p.round_due(settings, next, passes_a_frame, round_frames)) return;
  } else {
    const bool due = next % period == 0 && next - p.last_tried >= period;
    const bool overdue = bound && p.last_tried && next - p.last_tried >= bound;
    if (!(due || overdue)) return;
  }
  // Earlier probes not yet measured: this one would only wait behind them (governing.hpp).
  if (p.pending.size() >= kMaxPending || governor_probes_backlogged()) return;
  p.last_tried = next;
  p.plan(next, sweeping || grouped, streams, round_frames > 0);
}

void ProbeFrames::collect(bool wait) {
  if (impl_->probe_possible()) impl_->collect(wait);
}

bool ProbeFrames::is_probe_frame(uint64_t frame) const { return frame && frame == impl_->frame; }
uint64_t ProbeFrames::frame_now() const { return impl_->frame; }
bool ProbeFrames::was_probe_frame(uint64_t frame) const { return impl_->recent_slot(frame) >= 0; }

int ProbeFrames::sweep_streams_of(uint64_t frame) const {
  const int k = impl_->recent_slot(frame);
  return k >= 0 ? impl_->recent_sweep_streams[k] : 0;
}

void ProbeFrames::prepare() {
  const AppSignalsDeferred deferred;
  hold_app_signals();  // until the swap (app_signals.hpp)
  if (impl_->frame) impl_->prepare(true, 0, -1);
}

void ProbeFrames::prepare_clear(GLbitfield mask, int draw_buffer) {
  const AppSignalsDeferred deferred;
  hold_app_signals();
  if (impl_->frame) impl_->prepare(false, mask, draw_buffer);
}

void ProbeFrames::prepare_blit() {
  const AppSignalsDeferred deferred;
  hold_app_signals();
  if (impl_->frame) impl_->prepare(false, 0, -1);
}

bool ProbeFrames::first(bool clearing) {
  Impl& p = *impl_;
  p.duplicating_clear = clearing;
  if (!p.begin_duplicate()) return false;
  if (p.advance()) return true;
  p.end_duplicate();
  return false;
}

bool ProbeFrames::next() { return impl_->advance(); }
void ProbeFrames::end() { impl_->end_duplicate(); }

void ProbeFrames::generate_mipmap(GLuint texture) {
  const AppSignalsDeferred deferred;
  hold_app_signals();  // until the swap (app_signals.hpp)
  Impl& p = *impl_;
  if (!p.frame || !pgl().GenerateMipmap) return;
  const OwnGlWork own(p.c);
  const ApplyGl& g = agl();
  const GLint bound = get(GL_TEXTURE_BINDING_2D);
  if (!texture) texture = static_cast<GLuint>(bound);
  p.generated_mipmaps.insert(texture);
  bool rebound = false;
  for (int s = 0; s < p.stream_count; ++s) {
    const auto shadow = p.streams[s].textures.find(texture);
    if (shadow == p.streams[s].textures.end() || shadow->second.kind != GL_TEXTURE_2D) continue;
    // A stream still following draws nothing; one that took the texture from stream 0 has it
    // made there.
    if (!p.streams[s].forked) continue;
    if (s > 0 && p.streams[s].lead == 0) {
      const auto lead = p.streams[0].textures.find(texture);
      if (lead != p.streams[0].textures.end() && lead->second.texture == shadow->second.texture) continue;
    }
    g.BindTexture(GL_TEXTURE_2D, shadow->second.texture);
    pgl().GenerateMipmap(GL_TEXTURE_2D);
    rebound = true;
  }
  if (rebound) g.BindTexture(GL_TEXTURE_2D, static_cast<GLuint>(bound));
}

void ProbeFrames::blit(const GLint* src, const GLint* dst, GLbitfield mask, GLenum filter) {
  const AppSignalsDeferred deferred;
  Impl& p = *impl_;
  if (!p.frame) return;
  const OwnGlWork own(p.c);
  const ApplyGl& g = agl();
  TargetScaler& t = *p.targets();
  const GLuint app_read = t.app_read_framebuffer(), app_draw = t.app_draw_framebuffer();
  const GLint draw = get(GL_DRAW_FRAMEBUFFER_BINDING), read = get(GL_READ_FRAMEBUFFER_BINDING);
  const GLint scissor = g.IsEnabled(GL_SCISSOR_TEST);
  for (int s = 0; s < p.stream_count; ++s) {
    Stream& st = p.streams[s];
    const Shadow* to = p.filled(st, app_draw);
    if (!st.complete || !st.forked || !to) continue;
    const Shadow& d = *to;
    // From the stream's own image of the source when the frame drew it, else its lead's, else
    // the app's.
    GLuint from = t.real_framebuffer(app_read);
    double rx = 1.0, ry = 1.0;
    t.stored_scale(app_read, &rx, &ry);
    const Shadow* own = p.filled(st, app_read);
    const Shadow* source = own ? own : p.lead_shadow(st, app_read);
    if (source) {
      from = source->fbo;
      rx = static_cast<double>(source->width) / source->app_width;
      ry = static_cast<double>(source->height) / source->app_height;
    }
    const double dx = static_cast<double>(d.width) / d.app_width, dy = static_cast<double>(d.height) / d.app_height;
    GLint from_rect[4], to_rect[4];
    scale_corners(src, rx, ry, from_rect);
    scale_corners(dst, dx, dy, to_rect);
    g.BindFramebuffer(GL_READ_FRAMEBUFFER, from);
    g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, d.fbo);
    if (scissor) g.Disable(GL_SCISSOR_TEST);  // the app's scissor box is in its own sizes
    g.BlitFramebuffer(from_rect[0], from_rect[1], from_rect[2], from_rect[3], to_rect[0], to_rect[1], to_rect[2],
                      to_rect[3], mask, filter);
    if (scissor) g.Enable(GL_SCISSOR_TEST);
  }
  g.BindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(read));
  g.BindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(draw));
}

}  // namespace glbudget
