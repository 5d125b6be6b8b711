// What the probes' known scene must log under the shim (see testapps/probes/common/known_scene.hpp).
#pragma once
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <map>
#include <system_error>
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
// Files the tests make (logs, the governor's selections beside them, images) go in one folder
// of the test process's, removed with all it holds when that process exits, whatever a test
// left behind: a failed check skips the test's own clean-up. A child forked from the test
// process exits without removing it.
class TestTempDir {
 public:
  TestTempDir() : owner_(getpid()), path_("/tmp/glbudget_it_" + std::to_string(owner_)) {
    std::filesystem::create_directories(path_);
  }
  ~TestTempDir() {
    std::error_code ignored;
    if (getpid() == owner_) std::filesystem::remove_all(path_, ignored);
  }
  TestTempDir(const TestTempDir&) = delete;
  TestTempDir& operator=(const TestTempDir&) = delete;
  const std::string& path() const { return path_; }

 private:
  pid_t owner_;
  std::string path_;
};
inline std::string temp_path(const std::string& name) {
  static const TestTempDir dir;
  return dir.path() + "/" + name;
}
