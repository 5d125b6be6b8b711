// cpu: an estimate for software rendering (llvmpipe renders on threads of this process).
// P = idle + (max - idle) * u with u = process CPU time / (wall time * cores). Integrated,
// that is a cumulative energy: E(t) = idle * t + (max - idle) * cpu_time(t) / cores.
#include <sched.h>
#include <time.h>

#include <cstdio>

#include "sources.hpp"

namespace glbudget::sensors {

namespace {

// Placeholder figures for a small laptop CPU package; `glbudget calibrate` or the user
// (cpu:idle=..,max=..) should set the machine's own.
constexpr double default_idle_w = 10.0;
constexpr double default_max_w = 45.0;

double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

unsigned usable_cores() {
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) > 0) return static_cast<unsigned>(CPU_COUNT(&set));
  return 1;
}

class CpuEstimateSource final : public Source {
 public:
  CpuEstimateSource(double idle_w, double max_w, unsigned cores, std::int64_t start_ns)
      : idle_w_(idle_w), max_w_(max_w), cores_(cores), start_ns_(start_ns), start_cpu_s_(process_cpu_seconds()) {}

  std::string_view name() const override { return "cpu"; }
  bool is_estimate() const override { return true; }
  std::string description() const override {
    char text[200];
    std::snprintf(text, sizeof text,
                  "estimate: %.3g W + (%.3g W - %.3g W) * u, u = process CPU time / "
                  "(wall time * %u cores)",
                  idle_w_, max_w_, idle_w_, cores_);
    return text;
  }

  Reading read(std::int64_t now_ns) override {
    return Reading{ReadStatus::ok, ReadingKind::energy_j, *energy_now_j(now_ns), {}};
  }

  std::optional<double> energy_now_j(std::int64_t now_ns) const override {
    const double wall_s = static_cast<double>(now_ns - start_ns_) * 1e-9;
    const double cpu_s = process_cpu_seconds() - start_cpu_s_;
    return idle_w_ * wall_s + (max_w_ - idle_w_) * cpu_s / cores_;
  }

 private:
  double idle_w_, max_w_;
  unsigned cores_;
  std::int64_t start_ns_;
  double start_cpu_s_;
};

std::int64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

}  // namespace

OpenResult open_cpu(const SensorSpec& spec, const SourceEnvironment&) {
  std::string error;
  double idle = default_idle_w, max = default_max_w;
  unsigned cores = usable_cores();
  if (!only_params(spec, {"idle", "max", "cores"}, error) || !param_number(spec, "idle", idle, error) ||
      !param_number(spec, "max", max, error) || !param_index(spec, "cores", cores, error))
    return unavailable(error);
  if (idle < 0.0 || max < idle)
    return unavailable("cpu sensor needs 0 <= idle <= max (got idle=" + std::to_string(idle) +
                       ", max=" + std::to_string(max) + ")");
  if (cores == 0) return unavailable("cpu sensor needs cores >= 1");
  return OpenResult{std::make_unique<CpuEstimateSource>(idle, max, cores, monotonic_ns()), {}};
}

}  // namespace glbudget::sensors
