// calibrate_load: the load that `glbudget calibrate` measures under the shim (see usage()).
#include <signal.h>
#include <time.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>

#include "egl_context.hpp"
#include "frames_in_flight.hpp"
#include "load_options.hpp"
#include "load_renderer.hpp"

namespace calibrate_load {
namespace {

volatile sig_atomic_t g_stop = 0;
void request_stop(int) { g_stop = 1; }

std::int64_t now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

void sleep_until(std::int64_t deadline_ns) {
  const timespec ts{static_cast<time_t>(deadline_ns / 1'000'000'000), static_cast<long>(deadline_ns % 1'000'000'000)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR && !g_stop) {
  }
}

LoadShape step_shape(const LoadOptions& o, int step) {
  LoadShape shape{o.batches, o.vertices, o.fragments};
  const double scale = std::pow(o.factor, step);
  auto grow = [&](std::int64_t& count) { count = std::llround(static_cast<double>(count) * scale); };
  switch (o.sweep) {
    case LoadOptions::Sweep::batches:
      grow(shape.batches);
      break;
    case LoadOptions::Sweep::vertices:
      grow(shape.vertices);
      break;
    case LoadOptions::Sweep::fragments:
      grow(shape.fragments);
      break;
    case LoadOptions::Sweep::none:
      break;
  }
  return shape;
}

struct StepResult {
  std::int64_t start_ns = 0, end_ns = 0, frames = 0;
};

// One step: frames for o.seconds (at least one). Its last frame finishes its work before the
// swap, so the energy between the step's first and last swaps is the step's own.
StepResult run_step(const LoadOptions& o, EglContext& context, LoadRenderer& renderer, FramesInFlight& in_flight) {
  const std::int64_t period_ns = o.fps > 0 ? std::llround(1e9 / o.fps) : 0;
  StepResult r;
  r.start_ns = now_ns();
  const std::int64_t end = r.start_ns + std::llround(o.seconds * 1e9);
  std::int64_t deadline = r.start_ns + period_ns;
  for (bool last = false; !last;) {
    renderer.draw_frame();
    ++r.frames;
    const std::int64_t now = now_ns();
    // A paced frame that ran late restarts the cadence instead of rushing to catch up.
    if (period_ns > 0 && now > deadline + period_ns) deadline = now;
    const std::int64_t presented = period_ns > 0 ? std::max(now, deadline) : now;
    last = g_stop || presented >= end || (o.frames > 0 && r.frames >= o.frames);
    if (last) glFinish();
    if (period_ns > 0) sleep_until(deadline);
    deadline += period_ns;
    context.swap_buffers();
    if (last)
      in_flight.forget();
    else
      in_flight.frame_submitted();
  }
  r.end_ns = now_ns();
  return r;
}

int run(const LoadOptions& o) {
  EglContext context(o.width, o.height);
  LoadRenderer renderer(step_shape(o, 0), o.width, o.height);
  FramesInFlight in_flight;
  // A first frame, outside every step: it carries the shader compile and the sensor's start.
  renderer.draw_frame();
  glFinish();
  context.swap_buffers();
  int late_in_a_row = 0;
  for (int step = 0; step < o.steps && !g_stop; ++step) {
    const LoadShape shape = step_shape(o, step);
    renderer.set_shape(shape);
    const StepResult r = run_step(o, context, renderer, in_flight);
    const double fps =
        static_cast<double>(r.frames) * 1e9 / static_cast<double>(std::max<std::int64_t>(1, r.end_ns - r.start_ns));
    const bool late = o.fps > 0 && fps < 0.5 * o.fps;
    std::printf("step %d batches %lld vertices %lld fragments %lld start_ns %lld end_ns %lld frames %lld late %d%s\n",
                step, static_cast<long long>(shape.batches), static_cast<long long>(shape.vertices),
                static_cast<long long>(shape.fragments), static_cast<long long>(r.start_ns),
                static_cast<long long>(r.end_ns), static_cast<long long>(r.frames), late ? 1 : 0,
                g_stop ? " interrupted" : "");
    std::fflush(stdout);
    late_in_a_row = late ? late_in_a_row + 1 : 0;
    if (o.stop_when_late > 0 && late_in_a_row >= o.stop_when_late) break;
  }
  return 0;
}

}  // namespace
}  // namespace calibrate_load

int main(int argc, char** argv) {
  const auto options = calibrate_load::parse_options(argc, argv);
  if (!options) return 2;
  if (options->help) {
    std::fputs(calibrate_load::usage(), stdout);
    return 0;
  }
  // Interrupted, the load ends its frame and exits normally, so whoever logs it flushes.
  struct sigaction sa {};
  sa.sa_handler = calibrate_load::request_stop;
  sigemptyset(&sa.sa_mask);
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &sa, nullptr);
  try {
    return calibrate_load::run(*options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "calibrate_load: %s\n", e.what());
    return 1;
  }
}
