// What the probes' known scene must log under the shim (see testapps/probes/common/known_scene.hpp).
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "run_process.hpp"

// In a sanitizer build (GLBUDGET_SANITIZED_RUN) a test's matrix takes each code path once; the
// plain build runs it whole.
#ifdef GLBUDGET_SANITIZED_RUN
inline constexpr bool kSanitizedRun = true;
#else
inline constexpr bool kSanitizedRun = false;
#endif

struct PassExpectation {
  int64_t batches, vertices, fragments, primitives;
};

// Scene at 64x64: pass A, then pass B.
inline const std::vector<PassExpectation> kKnownScene = {{2, 12, 4096, 4}, {3, 18, 768, 6}};

struct LogCheck {
  size_t rows = 0;           // data rows
  size_t measured_rows = 0;  // rows with every GPU field present
};

// Paths from the build.
inline std::string probe_path(const std::string& name) { return std::string(PROBE_DIR) + "/" + name; }
inline std::string shim_path() { return SHIM_PATH; }
inline std::string temp_path(const std::string& name) {
  return "/tmp/glbudget_it_" + std::to_string(getpid()) + "_" + name;
}
