/* A stand-in for libnvidia-ml built by the tests, so that the nvml sensor's real dlopen/dlsym
 * path is exercised without an NVIDIA driver. FAKE_NVML_MODE selects the GPU it pretends to be:
 *   energy      total energy counter (rising 25 mJ per call) and power usage
 *   power       no energy counter (NVML_ERROR_NOT_SUPPORTED), 42.5 W power usage
 *   no_driver   nvmlInit fails with NVML_ERROR_DRIVER_NOT_LOADED
 *   lost        energy mode, but the GPU falls off the bus after 3 energy reads */
#include <stdlib.h>
#include <string.h>

typedef int nvmlReturn_t;
typedef struct nvmlDevice_st* nvmlDevice_t;
enum {
  SUCCESS = 0,
  ERROR_INVALID_ARGUMENT = 2,
  ERROR_NOT_SUPPORTED = 3,
  ERROR_DRIVER_NOT_LOADED = 9,
  ERROR_GPU_IS_LOST = 15
};

static int mode_is(const char* mode) {
  const char* value = getenv("FAKE_NVML_MODE");
  return value && strcmp(value, mode) == 0;
}

static int device_token;
static unsigned long long energy_mj = 1000000;
static int energy_reads;

nvmlReturn_t nvmlInit_v2(void) { return mode_is("no_driver") ? ERROR_DRIVER_NOT_LOADED : SUCCESS; }
nvmlReturn_t nvmlShutdown(void) { return SUCCESS; }

const char* nvmlErrorString(nvmlReturn_t code) {
  switch (code) {
    case ERROR_NOT_SUPPORTED:
      return "Not Supported";
    case ERROR_DRIVER_NOT_LOADED:
      return "Driver Not Loaded";
    case ERROR_GPU_IS_LOST:
      return "GPU is lost";
    case ERROR_INVALID_ARGUMENT:
      return "Invalid Argument";
    default:
      return "Unknown Error";
  }
}

nvmlReturn_t nvmlDeviceGetHandleByIndex_v2(unsigned index, nvmlDevice_t* device) {
  if (index != 0) return ERROR_INVALID_ARGUMENT;
  *device = (nvmlDevice_t)&device_token;
  return SUCCESS;
}

nvmlReturn_t nvmlDeviceGetTotalEnergyConsumption(nvmlDevice_t device, unsigned long long* mj) {
  if (device != (nvmlDevice_t)&device_token) return ERROR_INVALID_ARGUMENT;
  if (mode_is("power")) return ERROR_NOT_SUPPORTED;
  if (mode_is("lost") && ++energy_reads > 3) return ERROR_GPU_IS_LOST;
  energy_mj += 25;
  *mj = energy_mj;
  return SUCCESS;
}

nvmlReturn_t nvmlDeviceGetPowerUsage(nvmlDevice_t device, unsigned* mw) {
  if (device != (nvmlDevice_t)&device_token) return ERROR_INVALID_ARGUMENT;
  *mw = 42500;
  return SUCCESS;
}
