// The per-draw hot path, inlined into every generated draw wrapper. A draw that stays in the
// current pass costs a TLS load, a branch and an add; everything else goes to slow_draw().
#pragma once
#include <cstdint>

namespace glbudget {

struct DrawCounter {
  bool ready = false;          // a segment is open for the current pass: just count
  uint64_t open_batches = 0;   // batches of the open segment
  bool slow_draw(uint64_t n);  // opens/switches segments; false: skip the draw (pass_counter.cpp)
};

// The DrawCounter of the context current on this thread (null: no context, nothing to count).
// initial-exec: the shim is preloaded, so its TLS is static and needs no __tls_get_addr call.
extern thread_local DrawCounter* t_draw __attribute__((tls_model("initial-exec")));

// False when the draw must not reach the driver: the configuration skips the current pass.
inline bool count_draw(uint64_t n) {
  DrawCounter* d = t_draw;
  if (!d) return true;
  if (d->ready) [[likely]] {
    d->open_batches += n;
    return true;
  }
  return d->slow_draw(n);
}

}  // namespace glbudget
