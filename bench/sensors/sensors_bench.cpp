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

#include <chrono>
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

// The render thread's per-swap call, with the sampling thread running.
void BM_on_swap(benchmark::State& state) {
  PowerSensor sensor(open("cpu"));
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  for (auto _ : state) benchmark::DoNotOptimize(sensor.on_swap(monotonic_now_ns()));
}
BENCHMARK(BM_on_swap);

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
    std::printf("\nCPU time per call, relative to clock_gettime(CLOCK_MONOTONIC) = %.1f ns:\n",
                baseline);
    for (const auto& [name, ns] : cpu_ns_)
      std::printf("  %-36s %10.1f ns  %8.1fx\n", name.c_str(), ns, ns / baseline);
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
    PowerSensor sensor(open(spec), options);
    std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  }
  const double used = process_cpu_seconds() - before;
  const double samples = seconds * 1000.0 / period_ms;
  std::printf("  %-8s %4d ms  %6.2f%% of one core  (%.1f us per sample incl. wake-up)\n",
              spec.c_str(), period_ms, 100.0 * used / seconds, 1e6 * used / samples);
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
  benchmark::Shutdown();
  return 0;
}
