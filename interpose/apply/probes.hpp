// Quality probes in lockstep (DESIGN.md, "Quality probes"; paper §6): every probe period a
// frame is drawn a second time while the app draws it, the way a stereo driver issues each
// draw once per eye. Right after each of the app's draws (and clears and blits) the same call
// is issued once per probe stream into that stream's shadow render targets, with the stream's
// configuration bound: its variant programs and its render-target scales. Textures the frame
// has drawn into are read from their shadow copies in the duplicate only. What the app sees,
// keeps and reads back is never touched.
//
// A stream draws only from its first call that would draw differently from the app's frame or
// from stream 0 (another level of the bound program's pass, another scale of the framebuffer
// drawn into): until then its images are that one's, and from then on each of its shadows
// starts from them (GLBUDGET_PROBE_FOLLOW=0: every stream draws the whole frame). A shadow
// first used by a clear of all of an image is not filled first.
//
// Streams: the best configuration s0 (unless the frame is drawn in it) and one configuration
// with every pass best but one at its cheapest level (s_i^lmax), the pass chosen in turn (or,
// with GLBUDGET_PROBE_ORDER=weighted, in turn until each has been probed, then by its last
// error × the frames since: loop/probe_order.hpp); with GLBUDGET_PROBE_SWEEP, once each pass in
// the scene has been probed, every one of them in one probe frame, timed just ahead of the
// governor's selections (ProbeFrames::Impl::sweep_due). At
// the swap each stream's window image and the app's own are captured at window size and read
// back behind a fence (never a stall); the governor thread turns them into errors
// (apply/governing.hpp).
//
// Left out of the duplicate (the probe still runs; what they draw is the app's): draws with
// transform feedback active, draws of programs with storage blocks or atomic counters (side
// effects), draws inside the app's occlusion queries, compute dispatches, glCopyTex*.
// A layer of an array texture or a cube map's face (a shadow renderer's cascades and faces,
// re-attached one after another), or the whole texture attached (a geometry shader choosing
// the layer), is drawn into the stream's own copy of the whole texture at the stream's scale,
// which the stream's draws then sample. Levels above 0 are not shadowed; contexts before
// GL 4.2 / GLES 3.1 are not probed.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "app_signals.hpp"
#include "configuration.hpp"
#include "gl_types.hpp"
#include "glbudget/manifest/manifest.hpp"

namespace glbudget {

struct ContextState;

// A probe frame, window-sized: image 0 is what the app showed, then one per stream. Either its
// images compared on the GPU (errors), or read back (RGBA8 rows bottom-up) for the governor
// thread to compare; both where GLBUDGET_DUMP_PROBES wants the images.
struct ProbeCapture {
  struct Compared {
    size_t a = 0, b = 0;  // images
    double error = 0.0;   // 1 - SSIM
  };
  uint64_t frame = 0;
  int context = 0;
  int width = 0, height = 0;
  Levels shown;
  std::vector<Levels> streams;
  std::vector<std::vector<uint8_t>> images;
  std::vector<Compared> errors;
  // Manifest passes (bit i, i < 64) that drew in this probe frame or the one before it: a pass
  // that drew in neither changes nothing in the image at any of its levels.
  uint64_t passes_drawn = ~uint64_t{0};
};

// The image of the best configuration s0: what the app showed, unless a stream drew it.
size_t best_image(const ProbeCapture& capture);
// The SSIM's scale for captures of this size: GLBUDGET_PROBE_SCALE, else Wang's rule.
int probe_ssim_scale(int width, int height);
// Whether manifest pass `i` is in the scene, given the passes that drew (bit i, i < 64; those
// beyond are taken as drawing): it scales render targets, which changes the image whether or
// not its own programs draw, or its programs drew.
bool pass_in_scene(const manifest::Pass& pass, size_t i, uint64_t passes_drawn);

class ProbeFrames {
 public:
  explicit ProbeFrames(ContextState& c);
  ~ProbeFrames();
  ProbeFrames(const ProbeFrames&) = delete;
  ProbeFrames& operator=(const ProbeFrames&) = delete;

  // At the swap, before the window is presented: ends a probe frame (captures the streams).
  void before_present();
  // After present, before the real swap: captures what the app showed, starts the read-back.
  void after_present();
  // After the swap: collects finished read-backs; decides whether frame `next` is a probe.
  void after_swap(uint64_t next);
  // Read-backs the GPU has finished reach the governor; wait: all of them (the context is
  // about to be destroyed or the process to exit, and the last probe frame is otherwise lost).
  void collect(bool wait);
  // The context is destroyed while current, in the middle of a probe frame: waits (bounded)
  // for the GPU to finish what the frame has drawn into the streams' shadows, before the
  // driver frees them with the context, and ends the frame.
  void abandon_frame();
  bool is_probe_frame(uint64_t frame) const;
  // One of the last probe frames (their rows are logged some frames later).
  bool was_probe_frame(uint64_t frame) const;
  // Of one of them: the streams it drew where it measured every pass at once, else 0.
  int sweep_streams_of(uint64_t frame) const;
  // This object while its context draws a probe frame, else null (for t_probe).
  ProbeFrames* drawing() { return is_probe_frame(frame_now()) ? this : nullptr; }

  // Before the app's draw, clear (of `mask`'s buffers; `draw_buffer`: the one a
  // glClearBuffer* clears, -1: all) or blit: the streams' shadows of the bound framebuffer
  // hold what the app's holds before the call.
  void prepare();
  void prepare_clear(GLbitfield mask, int draw_buffer);
  void prepare_blit();

  // The duplicate of one draw: first() saves state and readies stream 0 (false: none for
  // this draw), next() the following stream, end() restores the app's state.
  bool first(bool clearing = false);
  bool next();
  void end();
  // After the app's clear or blit: the same into each stream's shadows.
  template <typename F>
  void clear(F&& call);
  void blit(const GLint* src, const GLint* dst, GLbitfield mask, GLenum filter);
  // After the app's glGenerateMipmap of a 2D texture (0: the one bound to GL_TEXTURE_2D):
  // each stream's shadow of it, where the frame drew one, gets its levels too.
  void generate_mipmap(GLuint texture);

 private:
  uint64_t frame_now() const;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Set while the context current on this thread draws a probe frame.
extern thread_local ProbeFrames* t_probe __attribute__((tls_model("initial-exec")));

template <typename F>
void ProbeFrames::clear(F&& call) {
  const AppSignalsDeferred deferred;
  if (!first(true)) return;
  do call();
  while (next());
  end();
}

// Called by every generated draw wrapper after the app's draw, on probe frames only.
template <typename F>
inline void probe_draw(F&& draw) {
  ProbeFrames* p = t_probe;
  const AppSignalsDeferred deferred;  // a duplicate may wait in the driver (app_signals.hpp)
  if (!p->first()) return;
  do draw();
  while (p->next());
  p->end();
}

// GLBUDGET_PROBE_PERIOD and GLBUDGET_DUMP_PROBES, for the governor thread.
struct ProbeSettings {
  uint64_t period = 0;  // frames between probe frames; 0: no probes
  // By default (GLBUDGET_PROBE_PERIOD not given) probes are that frequent only until every
  // pass has been probed once, then this many times rarer: a probe frame costs several frames.
  uint64_t settled_factor = 1;
  // The governor may ask for rarer settled probes (set_probe_period_wanted); not when the user
  // gave GLBUDGET_PROBE_PERIOD.
  bool stretchable = false;
  std::string dump_dir;  // where probe images go as PPM files ("" : nowhere)
};
const ProbeSettings& probe_settings();

// Governor thread: frames between settled probes it asks for at least (0: the settled period
// of ProbeSettings), whether bursts (every pass again after the scene moved) keep it too, and
// where sweeps were asked for, the most streams a probe frame is to draw (Governor::
// probe_streams_fit; 0: no limit): all of them sweep, fewer take the passes in turn that many
// at a time.
// Render thread: the period its contexts plan probes at now, for the governor's probe overhead
// (0: none planned yet).
void set_probe_period_wanted(uint64_t frames, bool bursts_too, int streams_fit = 0);
uint64_t probe_period_in_force();
// Render thread: the streams a settled probe frame draws where it measures every pass at once
// (GLBUDGET_PROBE_SWEEP: the best and one a pass in the scene), for the governor's probe
// overhead; 0 where probes take one pass each.
int probe_sweep_streams();
// The streams a sweep would draw where the user asked for sweeps, whether or not the governor
// has the shim sweep now (streams_fit above); 0: not asked.
int probe_sweepable_streams();
// Governor thread: the frame its next selection is due at, and the frames between selections
// (GLBUDGET_PROBE_SWEEP: settled probe frames measure every pass just ahead of it; 0: none due),
// and whether it is moving to the configuration it selected (a sweep at the longest gap waits
// for the configuration selected with room for it).
void set_probe_selection_due(uint64_t frame, uint64_t select_frames, bool transitioning = false);
// Governor thread: manifest pass `pass`'s latest error at its cheapest level (0 where it is not
// in the scene), by which settled probes choose the pass they take (loop/probe_order.hpp).
void set_probe_pass_error(size_t pass, double error);

}  // namespace glbudget
