#include "counter_buffers.hpp"

#include <atomic>
#include <cstring>

#include "dump_registry.hpp"
#include "gl_calls.hpp"

namespace glbudget {

namespace {
constexpr uint64_t kCopyPeriodFrames = 4;  // a readback every few frames is plenty for averages

std::atomic<uint64_t> g_next_source{1};

// Saves a buffer binding and restores it when leaving the scope.
class SavedBinding {
 public:
  SavedBinding(GLenum target, GLenum binding_query) : target_(target) {
    GLint name = 0;
    gl().GetIntegerv(binding_query, &name);
    name_ = static_cast<GLuint>(name);
  }
  ~SavedBinding() { gl().BindBuffer(target_, name_); }
  SavedBinding(const SavedBinding&) = delete;
  SavedBinding& operator=(const SavedBinding&) = delete;

 private:
  GLenum target_;
  GLuint name_ = 0;
};
}  // namespace

bool CounterBuffers::create(Entry& e) {
  const GlCalls& g = gl();
  GLuint names[2] = {0, 0};
  g.GenBuffers(2, names);
  e.counters = names[0];
  e.staging = names[1];
  if (!e.counters || !e.staging) return false;
  const instrument::CounterWords zeros{};
  SavedBinding saved(GL_COPY_WRITE_BUFFER, GL_COPY_WRITE_BUFFER_BINDING);
  g.BindBuffer(GL_COPY_WRITE_BUFFER, e.counters);
  g.BufferData(GL_COPY_WRITE_BUFFER, instrument::kCounterBytes, zeros.data(), GL_DYNAMIC_COPY);
  g.BindBuffer(GL_COPY_WRITE_BUFFER, e.staging);
  g.BufferData(GL_COPY_WRITE_BUFFER, instrument::kCounterBytes, nullptr, GL_STREAM_READ);
  return true;
}

void CounterBuffers::bind(uint64_t key, const std::vector<std::string>& program_hashes) {
  Entry& e = entries_[key];
  if (!e.counters) {
    e.program_hashes = program_hashes;
    e.source = g_next_source++;
    if (!create(e)) return;
  }
  e.drawn_since_copy = true;
  // glBindBufferBase also sets the generic binding, which the app may rely on.
  SavedBinding saved(GL_SHADER_STORAGE_BUFFER, GL_SHADER_STORAGE_BUFFER_BINDING);
  gl().BindBufferBase(GL_SHADER_STORAGE_BUFFER, static_cast<GLuint>(binding_), e.counters);
}

void CounterBuffers::forget(uint64_t key) {
  auto it = entries_.find(key);
  if (it == entries_.end()) return;
  Entry& e = it->second;
  // What the program drew since the last harvest is read before its buffer goes, waiting for
  // the GPU (a link is no place an app expects speed): a program relinked, or a name that
  // glDeleteProgram freed and the next glCreateProgram may reuse (an app's scenes one after
  // another), otherwise lost its last frames' counts, and all of them where it drew for fewer
  // frames than a copy takes to come back on a busy machine.
  if (e.counters && (e.fence || e.drawn_since_copy)) {
    read_now(e);
    dump_registry::write_changed();
  }
  release(e);
  entries_.erase(it);
}

void CounterBuffers::release(Entry& e) {
  const GlCalls& g = gl();
  if (e.fence) g.DeleteSync(e.fence);
  e.fence = nullptr;
  GLuint names[2] = {e.counters, e.staging};
  g.DeleteBuffers(2, names);
  e.counters = e.staging = 0;
}

void CounterBuffers::start_copy(Entry& e) {
  const GlCalls& g = gl();
  {
    SavedBinding read(GL_COPY_READ_BUFFER, GL_COPY_READ_BUFFER_BINDING);
    SavedBinding write(GL_COPY_WRITE_BUFFER, GL_COPY_WRITE_BUFFER_BINDING);
    g.BindBuffer(GL_COPY_READ_BUFFER, e.counters);
    g.BindBuffer(GL_COPY_WRITE_BUFFER, e.staging);
    g.CopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0, 0, instrument::kCounterBytes);
  }
  e.fence = g.FenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  e.drawn_since_copy = false;
}

void CounterBuffers::harvest(Entry& e, GLuint buffer) {
  const GlCalls& g = gl();
  instrument::CounterWords words{};
  {
    SavedBinding read(GL_COPY_READ_BUFFER, GL_COPY_READ_BUFFER_BINDING);
    g.BindBuffer(GL_COPY_READ_BUFFER, buffer);
    const void* mapped = g.MapBufferRange(GL_COPY_READ_BUFFER, 0, instrument::kCounterBytes, GL_MAP_READ_BIT);
    if (!mapped) return;
    std::memcpy(words.data(), mapped, instrument::kCounterBytes);
    g.UnmapBuffer(GL_COPY_READ_BUFFER);
  }
  for (const std::string& hash : e.program_hashes) dump_registry::set_counters(hash, e.source, words);
}

void CounterBuffers::poll(uint64_t frame) {
  const GlCalls& g = gl();
  bool harvested = false;
  for (auto& [key, e] : entries_) {
    if (e.fence) {
      GLenum state = g.ClientWaitSync(e.fence, 0, 0);  // timeout 0: a poll, never a wait
      if (state != GL_ALREADY_SIGNALED && state != GL_CONDITION_SATISFIED) continue;
      g.DeleteSync(e.fence);
      e.fence = nullptr;
      harvest(e, e.staging);
      harvested = true;
    }
    if (e.counters && e.drawn_since_copy && frame % kCopyPeriodFrames == 0) start_copy(e);
  }
  if (harvested) dump_registry::write_changed();
}

void CounterBuffers::read_now(Entry& e) {
  if (e.fence) {
    gl().DeleteSync(e.fence);
    e.fence = nullptr;
  }
  harvest(e, e.counters);  // mapping waits for the draws that write it
}

void CounterBuffers::read_all_now() {
  for (auto& [key, e] : entries_)
    if (e.counters) read_now(e);
  dump_registry::write_changed();
}

}  // namespace glbudget
