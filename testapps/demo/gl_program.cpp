#include "gl_program.hpp"

#include <stdexcept>

namespace demo {
namespace {

GLuint compile(GLenum stage, const std::vector<std::string_view>& sources, const Defines& defines) {
  std::string preamble = "#version 330 core\n";
  for (const auto& [name, value] : defines) preamble += "#define " + name + " " + value + "\n";
  std::vector<const GLchar*> strings{preamble.c_str()};
  std::vector<GLint> lengths{static_cast<GLint>(preamble.size())};
  for (std::string_view source : sources) {
    strings.push_back(source.data());
    lengths.push_back(static_cast<GLint>(source.size()));
  }
  const GLuint shader = glCreateShader(stage);
  glShaderSource(shader, static_cast<GLsizei>(strings.size()), strings.data(), lengths.data());
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLchar log[4096] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    glDeleteShader(shader);
    throw std::runtime_error(std::string("shader compilation failed (") + preamble + "): " + log);
  }
  return shader;
}

}  // namespace

Program::Program(const std::vector<std::string_view>& vertex_sources,
                 const std::vector<std::string_view>& fragment_sources, const Defines& defines) {
  const GLuint vs = compile(GL_VERTEX_SHADER, vertex_sources, defines);
  GLuint fs = 0;
  try {
    fs = compile(GL_FRAGMENT_SHADER, fragment_sources, defines);
  } catch (...) {
    glDeleteShader(vs);
    throw;
  }
  id_ = glCreateProgram();
  glAttachShader(id_, vs);
  glAttachShader(id_, fs);
  glLinkProgram(id_);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = GL_FALSE;
  glGetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLchar log[4096] = {};
    glGetProgramInfoLog(id_, sizeof log, nullptr, log);
    glDeleteProgram(id_);
    throw std::runtime_error(std::string("program link failed: ") + log);
  }
}

Program::~Program() { glDeleteProgram(id_); }

GLint Program::uniform(const char* name) const {
  const auto found = uniforms_.find(name);
  if (found != uniforms_.end()) return found->second;
  const GLint location = glGetUniformLocation(id_, name);
  uniforms_.emplace(name, location);
  return location;
}

}  // namespace demo
