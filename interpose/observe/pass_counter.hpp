// Per-context measurement of each frame's work per pass: CPU-counted batches and, through
// pools of GL queries, vertex/fragment shader invocations, primitives and GPU time. Query
// results are collected at later swaps only once available: the shim never waits on the GPU.
#pragma once
#include <cstdint>
#include <deque>
#include <functional>
#include <string>
#include <vector>

#include "draw_count.hpp"
#include "frame_row.hpp"
#include "gl_types.hpp"

namespace glbudget {

struct GlCaps {
  bool gles = false;
  int major = 0, minor = 0;
  bool pipeline_stats = false;  // ARB_pipeline_statistics_query / GL 4.6
  bool timer = false;           // ARB_timer_query / GL 3.3 (GL_TIMESTAMP counters)
  bool query_buffer = false;    // ARB_query_buffer_object / GL 4.4: a bound buffer redirects reads
  // Framebuffer objects with glBlitFramebuffer under their core names: GL 3.0, GLES 3.0, or
  // ARB_framebuffer_object (desktop GL 2.x drivers: vc4, lima, i915g).
  bool framebuffer_blit = false;
};
GlCaps detect_caps();
// The current context's driver has `name` (GL_EXTENSIONS), and GLBUDGET_TEST_HIDE_EXTENSIONS does
// not hide it.
bool has_extension(const GlCaps& caps, const char* name);

class PassCounter : public DrawCounter {
 public:
  // The statistics targets we use; the app may hold any of them (see app_query_*).
  enum Stat { kVertices, kFragments, kPrimitives, kStatCount };
  static const GLenum kStatTargets[kStatCount];

  explicit PassCounter(const GlCaps& caps) : caps_(caps) {}

  void set_pass(PassId pass);  // the pass later draws belong to (program change)
  void set_counting(bool on);  // off while a display list is being compiled
  void set_skipping(bool on);  // the configuration skips the current pass: draws are dropped
  // Every draw takes the slow path while on (the draw hook must run before each: a program in
  // app coordinates takes the uniforms of the textures bound for that draw).
  void set_every_draw_hooked(bool on);
  // The next draw takes the slow path (the draw framebuffer changed): `hook` runs there first.
  void invalidate() { ready = false; }
  void set_draw_hook(void (*hook)(void*), void* arg) {
    draw_hook_ = hook;
    draw_hook_arg_ = arg;
  }
  bool draw_slow(uint64_t n);
  // The configuration drawing this frame (the log's configuration column).
  void set_configuration(const char* text) { configuration_ = text; }

  // The app begins/ends one of its own queries. Ours on that target is closed first, and
  // segments stay unmeasured for it while the app holds it. Returns true if the target is ours.
  bool app_query_begin(GLenum target);
  bool app_query_end(GLenum target);
  bool app_holds(GLenum target) const;
  bool our_query_active(GLenum target) const;

  // Ends our queries before the context stops being current here (released, or destroyed while
  // current): llvmpipe frees a query that is still active at destruction without waiting for
  // the rasterizer threads that write it. The frame goes on; its next draw opens a new segment.
  void suspend() {
    if (open_) close_segment();
  }

  // Frame boundary (before the real swap): closes the open segment and queues the frame.
  void end_frame(uint64_t frame, int64_t time_ns, int context_index, const sensors::FrameEnergy& energy);
  // Turns queued frames into rows, never waiting on the GPU:
  //   kAvailable: frames whose results are all available (oldest first); a frame still
  //               pending after kMaxPendingFrames is given up and logged with CPU figures;
  //   kWait:      every frame, waiting for its results: only where nothing is left to stall
  //               (the context is being destroyed while current, or the process exits);
  //   kCpuOnly:   every frame with CPU figures only, with no GL call (context not current).
  enum class Collect { kAvailable, kWait, kCpuOnly };
  void collect(const std::function<void(const FrameRow&)>& emit, Collect mode);

  // After fork: frames queued before belong to the parent.
  void discard_pending() {
    pending_.clear();
    building_ = Frame{};
  }

  size_t pending_frames() const { return pending_.size(); }
  uint64_t frames_lost() const { return frames_lost_; }

 private:
  struct Segment {
    PassId pass = kFixedFunctionPass;
    uint64_t batches = 0;
    GLuint stat_query[kStatCount] = {0, 0, 0};  // 0: not measured
    GLuint ts_begin = 0, ts_end = 0;
  };
  struct Frame {
    uint64_t number = 0;
    int64_t time_ns = 0;
    int context = 0;
    sensors::FrameEnergy energy;
    std::string configuration;
    std::vector<Segment> segments;
  };

  // The inline fast path may count a draw: counting, not skipping, no hook wanted before each
  // draw, and the open segment is the current pass's.
  void update_ready() { ready = counting_ && !skipping_ && !every_draw_hooked_ && open_ && seg_.pass == pass_; }
  void open_segment();
  void close_segment();
  // A query object keeps the target it was first used with: one pool per target.
  enum Pool { kPoolTimestamp = kStatCount, kPoolCount };
  GLuint take_query(int pool);
  bool frame_available(const Frame& f) const;
  void emit_frame(Frame& f, bool read_gpu, const std::function<void(const FrameRow&)>& emit);
  void recycle(Frame& f);

  GlCaps caps_;
  PassId pass_ = kFixedFunctionPass;
  bool counting_ = true;
  bool skipping_ = false;
  bool every_draw_hooked_ = false;
  void (*draw_hook_)(void*) = nullptr;
  void* draw_hook_arg_ = nullptr;
  std::string configuration_;
  bool open_ = false;
  Segment seg_;
  unsigned app_held_ = 0;  // bit per Stat the app holds
  unsigned ours_active_ = 0;
  Frame building_;
  std::deque<Frame> pending_;
  std::vector<GLuint> free_queries_[kPoolCount];
  uint64_t frames_lost_ = 0;
};

}  // namespace glbudget
