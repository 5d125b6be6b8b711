// A headless OpenGL context for integration tests: EGL surfaceless (Mesa), no window.
#pragma once

#include <string>

namespace glbudget::test {

class EglContext {
 public:
  // profile: "core" (4.5 core) or "compatibility" (4.5 compatibility).
  explicit EglContext(const std::string& profile = "core");
  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  bool ok() const { return error_.empty(); }
  const std::string& error() const { return error_; }

 private:
  void* display_ = nullptr;
  void* context_ = nullptr;
  std::string error_;
};

}  // namespace glbudget::test
