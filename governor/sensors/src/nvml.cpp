// nvml: NVIDIA GPUs through libnvidia-ml, loaded with dlopen at run time (never linked, so
// glbudget runs on machines without the driver). Prefers the total energy counter (mJ, Volta
// and newer); falls back to power usage (mW), which newer drivers report as a 1-second
// average, so per-frame figures from it are smoothed.
#include <dlfcn.h>

#include "sources.hpp"

namespace glbudget::sensors {

namespace {

// The few NVML declarations needed (nvml.h is not installed on most machines).
using nvmlReturn_t = int;
using nvmlDevice_t = struct nvmlDevice_st*;
constexpr nvmlReturn_t NVML_SUCCESS = 0;

struct NvmlApi {
  void* library = nullptr;
  nvmlReturn_t (*init)() = nullptr;
  nvmlReturn_t (*shutdown)() = nullptr;
  const char* (*error_string)(nvmlReturn_t) = nullptr;
  nvmlReturn_t (*device_by_index)(unsigned, nvmlDevice_t*) = nullptr;
  nvmlReturn_t (*total_energy)(nvmlDevice_t, unsigned long long*) = nullptr;  // mJ
  nvmlReturn_t (*power_usage)(nvmlDevice_t, unsigned*) = nullptr;             // mW

  std::string describe(nvmlReturn_t code) const {
    return error_string ? error_string(code) : "NVML error " + std::to_string(code);
  }
};

template <typename F>
bool resolve(void* library, const char* symbol, F& function) {
  function = reinterpret_cast<F>(dlsym(library, symbol));
  return function != nullptr;
}

class NvmlSource final : public Source {
 public:
  NvmlSource(NvmlApi api, nvmlDevice_t device, unsigned index, bool has_energy)
      : api_(api), device_(device), index_(index), has_energy_(has_energy) {}
  ~NvmlSource() override {
    api_.shutdown();
    dlclose(api_.library);
  }

  std::string_view name() const override { return "nvml"; }
  std::string description() const override {
    return "GPU " + std::to_string(index_) +
           (has_energy_ ? " total energy consumption counter"
                        : " power usage (no energy counter on this GPU; newer drivers average "
                          "it over 1 s)");
  }

  Reading read(std::int64_t) override {
    Reading reading;
    nvmlReturn_t code;
    if (has_energy_) {
      unsigned long long millijoules = 0;
      code = api_.total_energy(device_, &millijoules);
      reading.kind = ReadingKind::energy_j;
      reading.value = static_cast<double>(millijoules) * 1e-3;
    } else {
      unsigned milliwatts = 0;
      code = api_.power_usage(device_, &milliwatts);
      reading.kind = ReadingKind::power_w;
      reading.value = milliwatts * 1e-3;
    }
    if (code != NVML_SUCCESS) {
      reading.status = ReadStatus::read_error;
      reading.detail = api_.describe(code);
    }
    return reading;
  }

 private:
  NvmlApi api_;
  nvmlDevice_t device_;
  unsigned index_;
  bool has_energy_;
};

}  // namespace

OpenResult open_nvml(const SensorSpec& spec, const SourceEnvironment& env) {
  std::string error;
  unsigned index = 0;
  if (!only_params(spec, {"device"}, error) || !param_index(spec, "device", index, error)) return unavailable(error);

  NvmlApi api;
  api.library = dlopen(env.nvml_library.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!api.library) return unavailable("cannot load " + env.nvml_library + " (no NVIDIA driver)");
  if (!resolve(api.library, "nvmlInit_v2", api.init) || !resolve(api.library, "nvmlShutdown", api.shutdown) ||
      !resolve(api.library, "nvmlDeviceGetHandleByIndex_v2", api.device_by_index) ||
      !resolve(api.library, "nvmlDeviceGetTotalEnergyConsumption", api.total_energy) ||
      !resolve(api.library, "nvmlDeviceGetPowerUsage", api.power_usage)) {
    dlclose(api.library);
    return unavailable(env.nvml_library + " lacks the NVML functions glbudget needs");
  }
  resolve(api.library, "nvmlErrorString", api.error_string);  // optional

  auto fail = [&](const std::string& what, nvmlReturn_t code) {
    const std::string why = what + ": " + api.describe(code);
    if (what != "nvmlInit") api.shutdown();
    dlclose(api.library);
    return unavailable(why);
  };
  if (const auto code = api.init(); code != NVML_SUCCESS) return fail("nvmlInit", code);
  nvmlDevice_t device = nullptr;
  if (const auto code = api.device_by_index(index, &device); code != NVML_SUCCESS)
    return fail("GPU " + std::to_string(index), code);

  unsigned long long millijoules = 0;
  const bool has_energy = api.total_energy(device, &millijoules) == NVML_SUCCESS;
  if (!has_energy) {
    unsigned milliwatts = 0;
    if (const auto code = api.power_usage(device, &milliwatts); code != NVML_SUCCESS)
      return fail("GPU " + std::to_string(index) + " reports neither energy nor power", code);
  }
  return OpenResult{std::make_unique<NvmlSource>(api, device, index, has_energy), {}};
}

}  // namespace glbudget::sensors
