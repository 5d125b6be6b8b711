#include "pass_counter.hpp"

#include <algorithm>
#include <string>
#include <string_view>
#include <vector>

#include "gl_calls.hpp"
#include "options.hpp"

namespace glbudget {

thread_local DrawCounter* t_draw = nullptr;

bool DrawCounter::slow_draw(uint64_t n) { return static_cast<PassCounter*>(this)->draw_slow(n); }

const GLenum PassCounter::kStatTargets[kStatCount] = {GL_VERTEX_SHADER_INVOCATIONS_ARB,
                                                      GL_FRAGMENT_SHADER_INVOCATIONS_ARB, GL_PRIMITIVES_SUBMITTED_ARB};

namespace {
constexpr size_t kMaxPendingFrames = 8;  // beyond this, a frame's GPU figures are given up
constexpr GLsizei kQueryChunk = 64;

int stat_index(GLenum target) {
  for (int i = 0; i < PassCounter::kStatCount; ++i)
    if (PassCounter::kStatTargets[i] == target) return i;
  return -1;
}

}  // namespace

bool has_extension(const GlCaps& caps, const char* name) {
  if (extension_hidden(name)) return false;  // GLBUDGET_TEST_HIDE_EXTENSIONS
  const GlCalls& g = gl();
  if (caps.major >= 3 && g.GetStringi) {
    const std::vector<std::string> names = extension_names();
    return std::find(names.begin(), names.end(), name) != names.end();
  }
  auto all = reinterpret_cast<const char*>(g.GetString(GL_EXTENSIONS));
  if (!all) return false;
  std::string_view list(all), want(name);
  for (size_t pos = 0; (pos = list.find(want, pos)) != std::string_view::npos; pos += want.size()) {
    size_t end = pos + want.size();
    if ((pos == 0 || list[pos - 1] == ' ') && (end == list.size() || list[end] == ' ')) return true;
  }
  return false;
}

GlCaps detect_caps() {
  GlCaps caps;
  const GlCalls& g = gl();
  auto version = reinterpret_cast<const char*>(g.GetString(GL_VERSION));
  if (!version) return caps;
  std::string_view v(version);
  caps.gles = v.rfind("OpenGL ES", 0) == 0;
  if (caps.gles)
    v.remove_prefix(v.find_first_of("0123456789") == std::string_view::npos ? v.size() : v.find_first_of("0123456789"));
  caps.major = v.size() > 0 ? v[0] - '0' : 0;
  caps.minor = v.size() > 2 ? v[2] - '0' : 0;
  auto at_least = [&](int M, int m) { return caps.major > M || (caps.major == M && caps.minor >= m); };
  // A feature of the core version from (M, m) on, or of the extension; a hidden extension
  // (GLBUDGET_TEST_HIDE_EXTENSIONS) hides the feature from every version.
  auto feature = [&](int M, int m, const char* extension) {
    return !extension_hidden(extension) && (at_least(M, m) || has_extension(caps, extension));
  };
  caps.framebuffer_blit = caps.gles ? caps.major >= 3 : feature(3, 0, "GL_ARB_framebuffer_object");
  // GLES lacks pipeline statistics and GL_TIMESTAMP counters in core; there we count batches.
  if (!caps.gles && g.BeginQuery && g.EndQuery && g.GetQueryObjectui64v) {
    caps.pipeline_stats = feature(4, 6, "GL_ARB_pipeline_statistics_query");
    caps.timer = g.QueryCounter && feature(3, 3, "GL_ARB_timer_query");
    caps.query_buffer = feature(4, 4, "GL_ARB_query_buffer_object");
  }
  return caps;
}

void PassCounter::set_pass(PassId pass) {
  pass_ = pass;
  update_ready();
}

void PassCounter::set_counting(bool on) {
  counting_ = on;
  update_ready();
}

void PassCounter::set_every_draw_hooked(bool on) {
  every_draw_hooked_ = on;
  update_ready();
}

void PassCounter::set_skipping(bool on) {
  skipping_ = on;
  update_ready();
}

bool PassCounter::draw_slow(uint64_t n) {
  if (!counting_) return true;  // compiling a display list: nothing is drawn now
  if (skipping_) return false;
  if (draw_hook_) draw_hook_(draw_hook_arg_);
  if (open_ && seg_.pass != pass_) close_segment();
  if (!open_) open_segment();
  open_batches += n;
  ready = !every_draw_hooked_;
  return true;
}

GLuint PassCounter::take_query(int pool) {
  std::vector<GLuint>& free = free_queries_[pool];
  if (free.empty()) {
    GLuint ids[kQueryChunk];
    gl().GenQueries(kQueryChunk, ids);
    free.assign(ids, ids + kQueryChunk);
  }
  GLuint q = free.back();
  free.pop_back();
  return q;
}

void PassCounter::open_segment() {
  const GlCalls& g = gl();
  seg_ = Segment{};
  seg_.pass = pass_;
  if (caps_.pipeline_stats) {
    for (int i = 0; i < kStatCount; ++i) {
      if (app_held_ & (1u << i)) continue;
      seg_.stat_query[i] = take_query(i);
      g.BeginQuery(kStatTargets[i], seg_.stat_query[i]);
      ours_active_ |= 1u << i;
    }
  }
  if (caps_.timer) {
    seg_.ts_begin = take_query(kPoolTimestamp);
    g.QueryCounter(seg_.ts_begin, GL_TIMESTAMP);
  }
  open_ = true;
  open_batches = 0;
}

void PassCounter::close_segment() {
  const GlCalls& g = gl();
  for (int i = 0; i < kStatCount; ++i) {
    if (ours_active_ & (1u << i)) g.EndQuery(kStatTargets[i]);
  }
  ours_active_ = 0;
  if (caps_.timer) {
    seg_.ts_end = take_query(kPoolTimestamp);
    g.QueryCounter(seg_.ts_end, GL_TIMESTAMP);
  }
  seg_.batches = open_batches;
  open_batches = 0;
  building_.segments.push_back(seg_);
  open_ = false;
  ready = false;
}

bool PassCounter::app_query_begin(GLenum target) {
  int i = stat_index(target);
  if (i < 0) return false;
  // Only one query per target may be active: ours yields. The segment so far is complete,
  // so it is closed with every statistic; the next one is opened without this target.
  if (open_) close_segment();
  app_held_ |= 1u << i;
  return true;
}

bool PassCounter::app_query_end(GLenum target) {
  int i = stat_index(target);
  if (i < 0 || !(app_held_ & (1u << i))) return false;
  app_held_ &= ~(1u << i);
  // Start a fresh segment at the next draw so that the statistic is measured again.
  if (open_) close_segment();
  return true;
}

bool PassCounter::app_holds(GLenum target) const {
  int i = stat_index(target);
  return i >= 0 && (app_held_ & (1u << i));
}

bool PassCounter::our_query_active(GLenum target) const {
  int i = stat_index(target);
  return i >= 0 && (ours_active_ & (1u << i));
}

void PassCounter::end_frame(uint64_t frame, int64_t time_ns, int context_index, const sensors::FrameEnergy& energy) {
  if (open_) close_segment();
  building_.number = frame;
  building_.time_ns = time_ns;
  building_.context = context_index;
  building_.energy = energy;
  building_.configuration = configuration_;
  pending_.push_back(std::move(building_));
  building_ = Frame{};
  // Swapping a window flushes anyway; swapping a pbuffer (or nothing) may not, and unflushed
  // queries never become available. A flush is not a wait.
  if (gl().Flush && (caps_.pipeline_stats || caps_.timer)) gl().Flush();
}

bool PassCounter::frame_available(const Frame& f) const {
  const GlCalls& g = gl();
  auto available = [&](GLuint q) {
    if (!q) return true;
    GLuint ok = 0;
    g.GetQueryObjectuiv(q, GL_QUERY_RESULT_AVAILABLE, &ok);
    return ok != 0;
  };
  // Results usually complete in submission order: test the newest first, the rest only then.
  for (auto it = f.segments.rbegin(); it != f.segments.rend(); ++it) {
    if (!available(it->ts_end) || !available(it->ts_begin)) return false;
    for (GLuint q : it->stat_query)
      if (!available(q)) return false;
  }
  return true;
}

void PassCounter::emit_frame(Frame& f, bool read_gpu, const std::function<void(const FrameRow&)>& emit) {
  const GlCalls& g = gl();
  struct Acc {
    FrameRow row;
    bool unmeasured[4] = {false, false, false, false};
  };
  std::vector<Acc> rows;  // few passes per frame: a linear search keeps first-use order
  auto read = [&](GLuint q) {
    GLuint64 v = 0;
    g.GetQueryObjectui64v(q, GL_QUERY_RESULT, &v);
    return static_cast<int64_t>(v);
  };
  for (const Segment& s : f.segments) {
    Acc* acc = nullptr;
    for (Acc& a : rows)
      if (a.row.pass == s.pass) acc = &a;
    if (!acc) {
      rows.emplace_back();
      acc = &rows.back();
      acc->row.frame = f.number;
      acc->row.time_ns = f.time_ns;
      acc->row.context = f.context;
      acc->row.pass = s.pass;
      acc->row.energy = f.energy;
      acc->row.configuration = f.configuration;
      acc->row.vertices = acc->row.fragments = acc->row.primitives = acc->row.gpu_ns = 0;
    }
    acc->row.batches += s.batches;
    int64_t* stat[kStatCount] = {&acc->row.vertices, &acc->row.fragments, &acc->row.primitives};
    for (int i = 0; i < kStatCount; ++i) {
      if (read_gpu && s.stat_query[i])
        *stat[i] += read(s.stat_query[i]);
      else
        acc->unmeasured[i] = true;
    }
    if (read_gpu && s.ts_begin && s.ts_end)
      acc->row.gpu_ns += read(s.ts_end) - read(s.ts_begin);
    else
      acc->unmeasured[3] = true;
  }
  for (Acc& a : rows) {
    int64_t* fields[4] = {&a.row.vertices, &a.row.fragments, &a.row.primitives, &a.row.gpu_ns};
    for (int i = 0; i < 4; ++i)
      if (a.unmeasured[i]) *fields[i] = -1;
    emit(a.row);
  }
}

void PassCounter::recycle(Frame& f) {
  for (const Segment& s : f.segments) {
    for (int i = 0; i < kStatCount; ++i)
      if (s.stat_query[i]) free_queries_[i].push_back(s.stat_query[i]);
    if (s.ts_begin) free_queries_[kPoolTimestamp].push_back(s.ts_begin);
    if (s.ts_end) free_queries_[kPoolTimestamp].push_back(s.ts_end);
  }
}

void PassCounter::collect(const std::function<void(const FrameRow&)>& emit, Collect mode) {
  if (pending_.empty()) return;
  const GlCalls& g = gl();
  const bool use_gl = mode != Collect::kCpuOnly;
  // A buffer bound to GL_QUERY_BUFFER would turn our reads into writes into the app's buffer.
  GLint query_buffer = 0;
  if (use_gl && caps_.query_buffer) {
    g.GetIntegerv(GL_QUERY_BUFFER_BINDING, &query_buffer);
    if (query_buffer) g.BindBuffer(GL_QUERY_BUFFER, 0);
  }
  while (!pending_.empty()) {
    Frame& f = pending_.front();
    const bool available = use_gl && (mode == Collect::kWait || frame_available(f));
    if (!available && mode == Collect::kAvailable && pending_.size() <= kMaxPendingFrames) break;
    if (!available) ++frames_lost_;
    emit_frame(f, available, emit);
    recycle(f);
    pending_.pop_front();
  }
  if (query_buffer) g.BindBuffer(GL_QUERY_BUFFER, static_cast<GLuint>(query_buffer));
}

}  // namespace glbudget
