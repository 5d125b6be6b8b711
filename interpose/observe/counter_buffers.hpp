// The GPU side of instrumentation in one context: a counter buffer per instrumented program
// (or pipeline), bound at the counter binding while it draws, and read back asynchronously
// (a copy and a fence, harvested at a later swap once the fence has signalled). Counters are
// never reset: each readback holds the totals since the program was linked.
#pragma once
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "gl_types.hpp"
#include "glbudget/instrument/instrument.hpp"

namespace glbudget {

class CounterBuffers {
 public:
  explicit CounterBuffers(int binding) : binding_(binding) {}
  CounterBuffers(const CounterBuffers&) = delete;
  CounterBuffers& operator=(const CounterBuffers&) = delete;

  // The draws that follow use `key`'s counters, credited in the dump to `program_hashes` (a
  // pipeline's programs: each reads the words of its own stages).
  void bind(uint64_t key, const std::vector<std::string>& program_hashes);
  // A relinked program starts a new count: its buffer is read a last time and dropped.
  void forget(uint64_t key);
  // At each swap: harvests finished copies, starts new ones every few frames. Never waits.
  void poll(uint64_t frame);
  // Reads every buffer now, waiting for the GPU: only when the context is going away.
  void read_all_now();

 private:
  struct Entry {
    std::vector<std::string> program_hashes;
    uint64_t source = 0;     // unique id of this buffer in the dump registry
    GLuint counters = 0;     // bound for the draws
    GLuint staging = 0;      // copy target, mapped once the copy's fence has signalled
    GLsync fence = nullptr;  // pending copy
    bool drawn_since_copy = false;
  };
  bool create(Entry& e);
  void start_copy(Entry& e);
  void harvest(Entry& e, GLuint buffer);
  // The counters themselves, waiting for the GPU; a pending copy is dropped.
  void read_now(Entry& e);
  void release(Entry& e);

  int binding_;
  std::unordered_map<uint64_t, Entry> entries_;
};

}  // namespace glbudget
