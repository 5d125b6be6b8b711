// The cpu estimate measured in a real process: threads burning both cores must read higher
// than the same process sleeping, and as much higher as the CPU time they actually got.
#include <catch2/catch.hpp>
#include <pthread.h>
#include <time.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "glbudget/sensors/registry.hpp"
#include "glbudget/sensors/sensor.hpp"

using namespace glbudget::sensors;
using namespace std::chrono_literals;

namespace {

constexpr double idle_w = 10.0, max_w = 50.0, cores = 2.0;

std::unique_ptr<PowerSensor> cpu_sensor() {
  std::string error;
  const auto spec = parse_sensor_spec("cpu:idle=10,max=50,cores=2", error);
  REQUIRE(spec);
  auto opened = open_source(*spec, SourceEnvironment{});
  REQUIRE(opened.source);
  return std::make_unique<PowerSensor>(std::move(opened.source));
}

double thread_cpu_seconds(std::thread& thread) {
  clockid_t clock;
  REQUIRE(pthread_getcpuclockid(thread.native_handle(), &clock) == 0);
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

struct Measured {
  double sensor_w;    // what the sensor reported for the interval
  double expected_w;  // the model applied to the burners' own CPU time (other threads idle)
};

// Mean power over `duration` while `busy_threads` threads spin.
Measured measure(PowerSensor& sensor, int busy_threads, std::chrono::milliseconds duration) {
  std::atomic<bool> stop{false};
  std::vector<std::thread> burners;
  for (int i = 0; i < busy_threads; ++i)
    burners.emplace_back([&] {
      volatile std::uint64_t x = 0;
      while (!stop.load(std::memory_order_relaxed)) x = x + 1;
    });
  auto burner_cpu = [&] {
    double sum = 0.0;
    for (auto& t : burners) sum += thread_cpu_seconds(t);
    return sum;
  };
  // Anchor the interval at a swap that already has a rate (as the shim's later frames do).
  double cpu_before = 0.0;
  std::int64_t start = 0;
  bool anchored = false;
  for (int attempt = 0; attempt < 1000 && !anchored; ++attempt) {
    if (attempt > 0) std::this_thread::sleep_for(2ms);
    cpu_before = burner_cpu();
    start = monotonic_now_ns();
    anchored = sensor.on_swap(start).valid;
  }
  REQUIRE(anchored);
  std::this_thread::sleep_for(duration);
  const std::int64_t end = monotonic_now_ns();
  const FrameEnergy frame = sensor.on_swap(end);
  const double cpu_during = burner_cpu() - cpu_before;
  stop = true;
  for (auto& t : burners) t.join();
  REQUIRE(frame.valid);
  const double u = cpu_during / (static_cast<double>(end - start) * 1e-9 * cores);
  return Measured{frame.mean_power_w, idle_w + (max_w - idle_w) * u};
}

}  // namespace

TEST_CASE("the cpu sensor reads more power when the process burns two cores than when idle", "[cpu]") {
  auto sensor = cpu_sensor();
  CHECK(sensor->name() == "cpu");
  CHECK(sensor->is_estimate());
  const Measured idle = measure(*sensor, 0, 300ms);
  const Measured busy = measure(*sensor, 2, 300ms);
  INFO("idle " << idle.sensor_w << " W, burning " << busy.sensor_w
               << " W (burners' own CPU "
                  "time predicts "
               << busy.expected_w << " W)");
  CHECK(idle.sensor_w >= idle_w - 1e-9);
  CHECK(idle.sensor_w < idle_w + 2.0);
  // The burners get two full cores only on an otherwise idle machine; whatever they got, the
  // sensor must have seen it (the sampler and this thread add a little).
  CHECK(busy.sensor_w == Approx(busy.expected_w).margin(2.0));
  CHECK(busy.sensor_w > idle.sensor_w + 4.0);  // at least 0.2 of a core for the burners
  CHECK(busy.sensor_w <= max_w + 0.5);
}

TEST_CASE("the cpu estimate is exact at each swap, with no sampling in between", "[cpu]") {
  auto sensor = cpu_sensor();
  std::atomic<bool> stop{false};
  std::thread burner([&] {
    volatile std::uint64_t x = 0;
    while (!stop.load(std::memory_order_relaxed)) x = x + 1;
  });
  auto process_cpu = [] {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
  };
  // The sensor reads the process's CPU time inside on_swap(); reading it just before and just
  // after brackets the sensor's value exactly, however the threads are scheduled.
  constexpr double k = (max_w - idle_w) / cores;
  std::int64_t previous_t = monotonic_now_ns();
  double previous_before = process_cpu();
  sensor->on_swap(previous_t);
  double previous_after = process_cpu();
  for (int frame = 0; frame < 20; ++frame) {
    std::this_thread::sleep_for(7ms);
    const std::int64_t t = monotonic_now_ns();
    const double before = process_cpu();
    const FrameEnergy e = sensor->on_swap(t);
    const double after = process_cpu();
    REQUIRE(e.valid);
    const double idle_j = idle_w * static_cast<double>(t - previous_t) * 1e-9;
    CHECK(e.energy_j >= idle_j + k * (before - previous_after) - 1e-9);
    CHECK(e.energy_j <= idle_j + k * (after - previous_before) + 1e-9);
    previous_t = t;
    previous_before = before;
    previous_after = after;
  }
  stop = true;
  burner.join();
}
