// A pbuffer swap never blocks, and a software renderer queues frames without bound. This keeps
// at most two frames ahead of the renderer, as a window's swap chain would, so that frames are
// timed as they are drawn rather than as they are queued.
#pragma once
#include <GL/glew.h>

#include <deque>

namespace calibrate_load {

class FramesInFlight {
 public:
  FramesInFlight() = default;
  FramesInFlight(const FramesInFlight&) = delete;
  FramesInFlight& operator=(const FramesInFlight&) = delete;
  ~FramesInFlight() { forget(); }

  // After a swap: waits until at most two frames are unfinished.
  void frame_submitted() {
    fences_.push_back(glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0));
    while (fences_.size() > kMaxFrames) {
      while (glClientWaitSync(fences_.front(), GL_SYNC_FLUSH_COMMANDS_BIT, 1'000'000'000) == GL_TIMEOUT_EXPIRED) {
      }
      glDeleteSync(fences_.front());
      fences_.pop_front();
    }
  }
  // After a glFinish: nothing is in flight.
  void forget() {
    for (GLsync fence : fences_) glDeleteSync(fence);
    fences_.clear();
  }

 private:
  static constexpr std::size_t kMaxFrames = 2;
  std::deque<GLsync> fences_;
};

}  // namespace calibrate_load
