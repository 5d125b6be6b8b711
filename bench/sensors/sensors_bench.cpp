// Sensor overhead: what one sample costs on the sampling thread, what on_swap() costs on the
// render thread, and the sampling thread's share of a core at the default period. Figures are
// printed as times and as ratios to a bare clock_gettime(CLOCK_MONOTONIC) in the same run.
//
// sysfs figures come from a fake tree on the local file system (this machine has no power
// sysfs); real sysfs attributes cost a little more (kernfs + the driver's read of the register).
#include <benchmark/benchmark.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <thread>

#include "glbudget/sensors/energy_integrator.hpp"
#include "glbudget/sensors/energy_timeline.hpp"
#include "glbudget/sensors/registry.hpp"
#include "glbudget/sensors/sensor.hpp"

namespace fs = std::filesystem;
using namespace glbudget::sensors;

namespace {

// A fake /sys with an amdgpu hwmon and two RAPL packages, removed at exit.
struct FakeTree {
  fs::path root;
  FakeTree() {
    std::string pattern = (fs::temp_directory_path() / "glbudget-bench-XXXXXX").string();
    if (!mkdtemp(pattern.data())) std::abort();
    root = pattern;
    write("class/hwmon/hwmon0/name", "amdgpu");
    write("class/hwmon/hwmon0/power1_average", "30000000");
    for (const char* zone : {"intel-rapl:0", "intel-rapl:1"}) {
      const std::string dir = std::string("class/powercap/") + zone;
      write(dir + "/name", std::string("package-") + zone[11]);
      write(dir + "/energy_uj", "123456789");
      write(dir + "/max_energy_range_uj", "262143328850");
    }
    mkfifo((root / "meter").c_str(), 0600);
  }
  ~FakeTree() { fs::remove_all(root); }
  void write(const std::string& relative, const std::string& text) const {
    fs::create_directories((root / relative).parent_path());
    std::ofstream(root / relative) << text << '\n';
  }
};

const FakeTree& tree() {
  static FakeTree instance;
  return instance;
}

std::unique_ptr<Source> open(const std::string& text) {
  std::string error;
  auto spec = parse_sensor_spec(text, error);
  SourceEnvironment env;
  env.sysfs_root = tree().root;
  auto opened = open_source(*spec, env);
  if (!opened.source) {
    std::fprintf(stderr, "cannot open %s: %s\n", text.c_str(), opened.why_not.c_str());
    std::abort();
  }
  return std::move(opened.source);
}

void BM_baseline_clock_monotonic(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(monotonic_now_ns());
}
BENCHMARK(BM_baseline_clock_monotonic);

void read_source(benchmark::State& state, const std::string& spec) {
  auto source = open(spec);
  std::int64_t t = 0;
  for (auto _ : state) benchmark::DoNotOptimize(source->read(t += 5'000'000));
}
void BM_read_cpu(benchmark::State& state) { read_source(state, "cpu"); }
void BM_read_amdgpu_hwmon(benchmark::State& state) { read_source(state, "amdgpu"); }
void BM_read_rapl_two_packages(benchmark::State& state) { read_source(state, "rapl"); }
void BM_read_file_meter_fifo_idle(benchmark::State& state) {
  read_source(state, "file:" + (tree().root / "meter").string());
}
BENCHMARK(BM_read_cpu);
BENCHMARK(BM_read_amdgpu_hwmon);
BENCHMARK(BM_read_rapl_two_packages);
BENCHMARK(BM_read_file_meter_fifo_idle);

// One whole sample of the sampling thread: read, judge, publish.
void BM_sample_cpu_integrate_publish(benchmark::State& state) {
  auto source = open("cpu");
  EnergyIntegrator integrator;
  EnergyTimeline timeline;
  for (auto _ : state) {
    const std::int64_t now = monotonic_now_ns();
    const auto outcome = integrator.accept(now, source->read(now));
    if (outcome.point) timeline.publish(*outcome.point);
  }
}
BENCHMARK(BM_sample_cpu_integrate_publish);

// Hides a source's energy_now_j, forcing the sampling-thread path (as for hardware counters).
class SampledOnly final : public Source {
 public:
  explicit SampledOnly(std::unique_ptr<Source> inner) : inner_(std::move(inner)) {}
  std::string_view name() const override { return inner_->name(); }
  std::string description() const override { return inner_->description(); }
  Reading read(std::int64_t now_ns) override { return inner_->read(now_ns); }

 private:
  std::unique_ptr<Source> inner_;
};

// The render thread's per-swap call: reading the timeline the sampling thread publishes...
void BM_on_swap_sampled(benchmark::State& state) {
  PowerSensor sensor(std::make_unique<SampledOnly>(open("cpu")));
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  for (auto _ : state) benchmark::DoNotOptimize(sensor.on_swap(monotonic_now_ns()));
}
BENCHMARK(BM_on_swap_sampled);

// ...or, for the cpu estimate, computing the energy at the swap itself.
void BM_on_swap_cpu_read_at_swap(benchmark::State& state) {
  PowerSensor sensor(open("cpu"));
  for (auto _ : state) benchmark::DoNotOptimize(sensor.on_swap(monotonic_now_ns()));
}
BENCHMARK(BM_on_swap_cpu_read_at_swap);

// Prints each benchmark's CPU time as a multiple of the baseline's.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& run : runs) cpu_ns_[run.benchmark_name()] = run.GetAdjustedCPUTime();
  }
  void Finalize() override {
    ConsoleReporter::Finalize();
    const double baseline = cpu_ns_["BM_baseline_clock_monotonic"];
    std::printf("\nCPU time per call, relative to clock_gettime(CLOCK_MONOTONIC) = %.1f ns:\n", baseline);
    for (const auto& [name, ns] : cpu_ns_) std::printf("  %-36s %10.1f ns  %8.1fx\n", name.c_str(), ns, ns / baseline);
  }

 private:
  std::map<std::string, double> cpu_ns_;
};

double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

// The sampling thread's whole cost (wake-ups included) while this thread sleeps.
void report_sampler_share(const std::string& spec, int period_ms) {
  constexpr double seconds = 2.0;
  SamplerOptions options;
  options.period = std::chrono::milliseconds(period_ms);
  const double before = process_cpu_seconds();
  {
    PowerSensor sensor(std::make_unique<SampledOnly>(open(spec)), options);
    std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  }
  const double used = process_cpu_seconds() - before;
  const double samples = seconds * 1000.0 / period_ms;
  std::printf("  %-8s %4d ms  %6.2f%% of one core  (%.1f us per sample incl. wake-up)\n", spec.c_str(), period_ms,
              100.0 * used / seconds, 1e6 * used / samples);
}

// Per-frame accuracy of the cpu estimate against the exact model value: the same formula
// applied to CLOCK_PROCESS_CPUTIME_ID read at each swap. Sampled on the thread (period_ms > 0),
// the difference is what sampling between swaps and extrapolating to the swap costs, as it
// would for a hardware counter; read at the swap (period_ms == 0), it should vanish.
void report_frame_accuracy(int period_ms) {
  constexpr double idle_w = 10.0, max_w = 45.0;
  constexpr int frames = 90;
  constexpr auto frame_time = std::chrono::microseconds(16'667);
  const double cores = 2.0;
  std::string error;
  const auto spec = parse_sensor_spec("cpu:idle=10,max=45,cores=2", error);
  SamplerOptions options;
  options.period = std::chrono::milliseconds(std::max(period_ms, 1));
  auto source = open_source(*spec, SourceEnvironment{}).source;
  PowerSensor sensor(period_ms > 0 ? std::make_unique<SampledOnly>(std::move(source)) : std::move(source), options);

  // A render-like load: one thread busy for the first half of each frame.
  std::atomic<bool> stop{false};
  std::thread load([&] {
    while (!stop) {
      const auto until = std::chrono::steady_clock::now() + frame_time / 2;
      while (std::chrono::steady_clock::now() < until) {
      }
      std::this_thread::sleep_for(frame_time / 2);
    }
  });
  double sum_sq = 0.0, sum_abs = 0.0, sum_exact = 0.0;
  int valid = 0;
  // Means over the governor's 30-frame fitting windows: per-frame errors largely cancel,
  // because each frame is differenced against the value reported at the previous swap.
  constexpr int window = 30;
  double window_sensor = 0.0, window_exact = 0.0, window_worst = 0.0;
  double previous_cpu = process_cpu_seconds();
  std::int64_t previous_t = monotonic_now_ns();
  sensor.on_swap(previous_t);
  auto next = std::chrono::steady_clock::now();
  for (int i = 0; i < frames + 10; ++i) {
    next += frame_time;
    std::this_thread::sleep_until(next);
    const std::int64_t t = monotonic_now_ns();
    const double cpu = process_cpu_seconds();
    const FrameEnergy frame = sensor.on_swap(t);
    const double dt = static_cast<double>(t - previous_t) * 1e-9;
    const double exact_w = idle_w + (max_w - idle_w) * (cpu - previous_cpu) / (dt * cores);
    previous_t = t;
    previous_cpu = cpu;
    if (i < 10 || !frame.valid) continue;  // warm-up
    const double e = frame.mean_power_w - exact_w;
    sum_sq += e * e;
    sum_abs += std::abs(e);
    sum_exact += exact_w;
    ++valid;
    window_sensor += frame.mean_power_w;
    window_exact += exact_w;
    if (valid % window == 0) {
      window_worst = std::max(window_worst, std::abs(window_sensor - window_exact) / window);
      window_sensor = window_exact = 0.0;
    }
  }
  stop = true;
  load.join();
  if (period_ms == 0)
    std::printf("  at swap");
  else
    std::printf("  %4d ms", period_ms);
  std::printf(
      "  mean exact %.2f W  per frame: mean |e| %.3f W, rms %.3f W;"
      "  30-frame mean: worst |e| %.3f W  (%d/%d frames valid)\n",
      sum_exact / valid, sum_abs / valid, std::sqrt(sum_sq / valid), window_worst, valid, frames);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  std::printf("\nSampling thread's share of a core by period (default 5 ms), over 2 s each:\n");
  for (int period_ms : {1, 5, 20}) report_sampler_share("cpu", period_ms);
  report_sampler_share("amdgpu", 5);
  report_sampler_share("rapl", 5);
  std::printf(
      "\ncpu estimate per 16.7 ms frame vs the exact model value at the swap, read at the\n"
      "swap (its default) or forced through the sampling thread at each period\n"
      "(one thread busy half of each frame; idle 10 W, max 45 W, 2 cores):\n");
  for (int period_ms : {0, 1, 5, 20}) report_frame_accuracy(period_ms);
  benchmark::Shutdown();
  return 0;
}
