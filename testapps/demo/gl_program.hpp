// A linked GLSL program built the way an engine does it: a version line, the quality
// #defines, then the source files, handed to glShaderSource as separate strings.
#pragma once
#include <GL/glew.h>

#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

namespace demo {

using Defines = std::vector<std::pair<std::string, std::string>>;

class Program {
 public:
  // Throws std::runtime_error with the driver's log when compiling or linking fails.
  Program(const std::vector<std::string_view>& vertex_sources, const std::vector<std::string_view>& fragment_sources,
          const Defines& defines = {});
  ~Program();
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;

  GLuint id() const { return id_; }
  void use() const { glUseProgram(id_); }
  GLint uniform(const char* name) const;  // cached; -1 when the compiler dropped it

 private:
  GLuint id_ = 0;
  mutable std::unordered_map<std::string, GLint> uniforms_;
};

}  // namespace demo
