// Frame boundaries: what happens around the app's swap, and the final flush at exit.
#pragma once

namespace glbudget {

struct ContextState;

enum class FlushMode {
  kCollect,  // frames whose results are available; the rest wait for a later swap
  kWait,     // everything, waiting for the GPU: the context is current and going away
  kCpuOnly,  // everything, CPU figures only: the context is not current here (no GL calls)
};

void flush_pending_frames(ContextState& c, FlushMode mode);

// Called when the first context is initialised: reads options, sets up exit and signal flushes.
void frame_output_started();

// Around the real swap of the context current on this thread (may be none).
void swap_begin();
void swap_end();

// Exit paths: rows of the current context and everything queued reach the file.
void final_flush();

}  // namespace glbudget
