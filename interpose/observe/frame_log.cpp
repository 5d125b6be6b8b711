#include "frame_log.hpp"

#include <cmath>

#include <fcntl.h>
#include <pthread.h>
#include <unistd.h>

#include <cerrno>
#include <cinttypes>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <vector>

#include "glbudget/sensors/power_log.hpp"
#include "signals_blocked.hpp"

namespace glbudget {

int format_row(const FrameRow& r, char* out, int size) {
  char pass[24];
  if (r.pass == kFixedFunctionPass)
    snprintf(pass, sizeof pass, "fixed-function");
  else
    snprintf(pass, sizeof pass, "%016" PRIx64, r.pass);
  char stat[4][24];
  const int64_t v[4] = {r.vertices, r.fragments, r.primitives, r.gpu_ns};
  for (int i = 0; i < 4; ++i) {
    if (v[i] < 0)
      stat[i][0] = '\0';
    else
      snprintf(stat[i], sizeof stat[i], "%" PRId64, v[i]);
  }
  char power[128];
  sensors::format_power_fields(r.energy, power, sizeof power);
  char governed[128] = "";  // three numbers of up to 31 characters, the decision
  if (r.decision) {
    auto number = [](double v, const char* format, char* text, size_t size) {
      if (std::isfinite(v))
        snprintf(text, size, format, v);
      else
        text[0] = '\0';
    };
    char p[32], b[32], e[32];
    number(r.predicted_w, "%.4f", p, sizeof p);
    number(r.budget_w, "%.4f", b, sizeof b);
    number(r.est_error, "%.6f", e, sizeof e);
    snprintf(governed, sizeof governed, "%s,%s,%s,%s", p, b, e, r.decision);
  } else {
    snprintf(governed, sizeof governed, ",,,");
  }
  char probe[40] = "";
  if (r.probe) {
    if (std::isfinite(r.probe_error))
      snprintf(probe, sizeof probe, "1,%.6f", r.probe_error);
    else
      snprintf(probe, sizeof probe, "1,");
  } else {
    snprintf(probe, sizeof probe, ",");
  }
  return snprintf(out, size, "%" PRIu64 ",%" PRId64 ",%d,%s,%" PRIu64 ",%s,%s,%s,%s,%s,%" PRIu64 ",%s,%s,%s,%s",
                  r.frame, r.time_ns, r.context, pass, r.batches, stat[0], stat[1], stat[2], stat[3], power,
                  r.energy.dropped_samples, r.configuration.c_str(), governed, probe, r.probe_streams.c_str());
}

struct FrameLog::Impl {
  std::mutex queue_mu;  // guards queue, stop, thread_started; held only briefly
  std::condition_variable wake;
  std::vector<FrameRow> queue;
  bool thread_started = false;
  pthread_t thread{};

  std::mutex file_mu;  // guards the file; held while writing
  int fd = -1;
  off_t written = 0;         // bytes of whole rows in the file
  bool open_failed = false;  // or a write failed (a full disk): rows are dropped from then on
  std::vector<FrameRow> writing;
  std::string text;  // the batch being written, whole rows only
  std::string file_path;
};

namespace {
// Set in every child forked without exec (an exec'd image starts afresh). Registered at load
// time because a child forked before the parent ever logged must not write the parent's file.
bool g_forked_child = false;
__attribute__((constructor)) void watch_forks() {
  pthread_atfork(nullptr, nullptr, [] { g_forked_child = true; });
}

// run.csv -> run.<pid>.csv (the child's own log).
std::string path_for_child(const std::string& path) {
  if (path.empty()) return path;
  std::string p = path;
  size_t slash = p.rfind('/');
  size_t dot = p.rfind('.');
  std::string pid = "." + std::to_string(getpid());
  if (dot != std::string::npos && (slash == std::string::npos || dot > slash))
    p.insert(dot, pid);
  else
    p += pid;
  return p;
}
}  // namespace

FrameLog::FrameLog() : impl_(new Impl) {
  // Keep the log consistent across fork(): no other thread may hold the locks in the child.
  pthread_atfork(
      [] {
        auto& l = get();
        l.impl_->file_mu.lock();
        l.impl_->queue_mu.lock();
      },
      [] {
        auto& l = get();
        l.impl_->queue_mu.unlock();
        l.impl_->file_mu.unlock();
      },
      [] { get().forked_child(); });
}

FrameLog& FrameLog::get() {
  static FrameLog* log = new FrameLog;  // never destroyed: rows may arrive during exit
  return *log;
}

void FrameLog::set_path(const std::string& path) {
  std::lock_guard lock(impl_->file_mu);
  path_ = path;
  impl_->file_path = g_forked_child ? path_for_child(path) : path;
}

void FrameLog::push(const FrameRow& row) {
  if (!enabled()) return;
  Impl& m = *impl_;
  std::unique_lock lock(m.queue_mu);
  m.queue.push_back(row);
  if (!m.thread_started) {
    m.thread_started = true;
    const SignalsBlocked blocked;  // the writer takes none of the app's signals
    pthread_create(&m.thread, nullptr, &FrameLog::writer_main, this);
    pthread_detach(m.thread);
  }
  lock.unlock();
  m.wake.notify_one();
}

void* FrameLog::writer_main(void* self) {
  auto* log = static_cast<FrameLog*>(self);
  Impl& m = *log->impl_;
  for (;;) {
    {
      std::unique_lock lock(m.queue_mu);
      m.wake.wait(lock, [&] { return !m.queue.empty(); });
    }
    std::lock_guard file_lock(m.file_mu);
    log->write_rows_locked();
  }
  return nullptr;
}

bool FrameLog::open_file_locked() {
  Impl& m = *impl_;
  if (m.fd >= 0) return true;
  if (m.open_failed) return false;
  m.fd = open(m.file_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (m.fd < 0) {
    m.open_failed = true;
    std::string msg = "glbudget: cannot write GLBUDGET_LOG file '" + m.file_path + "'; frames are not logged\n";
    (void)!write(STDERR_FILENO, msg.data(), msg.size());
    return false;
  }
  m.written = 0;
  return write_text_locked(std::string(kFrameLogHeader) + "\n");
}

// One write() per batch of whole rows (no stdio buffer that spills part of a row when it
// fills), so a process killed at any moment leaves only whole rows. A failed or short write
// (a full disk) is cut back to the last whole row, said once, and ends logging.
bool FrameLog::write_text_locked(const std::string& text) {
  Impl& m = *impl_;
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = write(m.fd, text.data() + done, text.size() - done);
    if (n > 0) {
      done += static_cast<size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    const int error = n < 0 ? errno : ENOSPC;
    if (done > 0) (void)!ftruncate(m.fd, m.written);  // no partial row left behind
    close(m.fd);
    m.fd = -1;
    m.open_failed = true;
    std::string msg = "glbudget: cannot write GLBUDGET_LOG file '" + m.file_path + "' (" + std::strerror(error) +
                      "); frames are no longer logged\n";
    (void)!write(STDERR_FILENO, msg.data(), msg.size());
    return false;
  }
  m.written += static_cast<off_t>(done);
  return true;
}

void FrameLog::write_rows_locked() {
  Impl& m = *impl_;
  {
    std::lock_guard lock(m.queue_mu);
    m.writing.swap(m.queue);
  }
  if (m.writing.empty() || !open_file_locked()) {
    m.writing.clear();
    return;
  }
  m.text.clear();
  char line[512];
  for (const FrameRow& r : m.writing) {
    const int n = format_row(r, line, sizeof line);
    if (n < 0) continue;
    if (static_cast<size_t>(n) < sizeof line) {
      m.text.append(line, static_cast<size_t>(n));
    } else {  // a long configuration column: format it again at its full length
      const size_t at = m.text.size();
      m.text.resize(at + static_cast<size_t>(n) + 1);
      format_row(r, m.text.data() + at, n + 1);
      m.text.resize(at + static_cast<size_t>(n));
    }
    m.text += '\n';
  }
  m.writing.clear();
  write_text_locked(m.text);
}

void FrameLog::drain() {
  if (!enabled()) return;
  std::lock_guard file_lock(impl_->file_mu);
  write_rows_locked();
}

void FrameLog::drain_from_signal() {
  if (!enabled()) return;
  // The signal may have interrupted a thread holding a lock: try for a while, never block.
  for (int i = 0; i < 2000; ++i) {
    if (impl_->file_mu.try_lock()) {
      if (impl_->queue_mu.try_lock()) {
        impl_->queue_mu.unlock();
        write_rows_locked();
        impl_->file_mu.unlock();
        return;
      }
      impl_->file_mu.unlock();
    }
    usleep(50);
  }
}

void FrameLog::forked_child() {
  Impl& m = *impl_;
  // The locks were taken in prepare by the forking thread, which is this thread now.
  m.queue.clear();  // the parent writes its own rows
  m.thread_started = false;
  if (m.fd >= 0) {
    close(m.fd);  // the parent's file
    m.fd = -1;
  }
  m.open_failed = false;
  m.file_path = path_for_child(path_);
  m.queue_mu.unlock();
  m.file_mu.unlock();
}

}  // namespace glbudget
