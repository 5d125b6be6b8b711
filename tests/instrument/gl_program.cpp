#include "gl_program.hpp"

#include <algorithm>
#include <regex>
#include <sstream>

namespace glbudget::test {

CompiledShader compile_shader(GLenum type, const std::string& source) {
  CompiledShader s;
  s.id = glCreateShader(type);
  const char* text = source.c_str();
  glShaderSource(s.id, 1, &text, nullptr);
  glCompileShader(s.id);
  GLint status = 0, length = 0;
  glGetShaderiv(s.id, GL_COMPILE_STATUS, &status);
  glGetShaderiv(s.id, GL_INFO_LOG_LENGTH, &length);
  s.log.resize(std::max(length, 1));
  glGetShaderInfoLog(s.id, length, nullptr, s.log.data());
  s.log.resize(std::max(length - 1, 0));
  s.ok = status == GL_TRUE;
  return s;
}

LinkedProgram link_program(const std::vector<GLuint>& shaders) {
  LinkedProgram p;
  p.id = glCreateProgram();
  for (GLuint s : shaders) glAttachShader(p.id, s);
  glLinkProgram(p.id);
  GLint status = 0, length = 0;
  glGetProgramiv(p.id, GL_LINK_STATUS, &status);
  glGetProgramiv(p.id, GL_INFO_LOG_LENGTH, &length);
  p.log.resize(std::max(length, 1));
  glGetProgramInfoLog(p.id, length, nullptr, p.log.data());
  p.log.resize(std::max(length - 1, 0));
  p.ok = status == GL_TRUE;
  return p;
}

namespace {

struct Interface {
  GLenum id;
  const char* name;
  std::vector<GLenum> properties;
};

}  // namespace

std::string interface_table(GLuint program, const std::string& skip_prefix) {
  const Interface interfaces[] = {
      {GL_UNIFORM, "uniform", {GL_TYPE, GL_ARRAY_SIZE, GL_LOCATION, GL_BLOCK_INDEX, GL_OFFSET}},
      {GL_UNIFORM_BLOCK, "uniform block", {GL_BUFFER_BINDING, GL_BUFFER_DATA_SIZE, GL_NUM_ACTIVE_VARIABLES}},
      {GL_PROGRAM_INPUT, "input", {GL_TYPE, GL_ARRAY_SIZE, GL_LOCATION}},
      {GL_PROGRAM_OUTPUT, "output", {GL_TYPE, GL_ARRAY_SIZE, GL_LOCATION, GL_LOCATION_INDEX}},
      {GL_SHADER_STORAGE_BLOCK, "storage block", {GL_BUFFER_BINDING, GL_BUFFER_DATA_SIZE}},
      {GL_BUFFER_VARIABLE, "buffer variable", {GL_TYPE, GL_ARRAY_SIZE, GL_OFFSET}},
  };
  std::vector<std::string> lines;
  for (const Interface& i : interfaces) {
    GLint count = 0;
    glGetProgramInterfaceiv(program, i.id, GL_ACTIVE_RESOURCES, &count);
    for (GLint r = 0; r < count; ++r) {
      char name[256] = {};
      glGetProgramResourceName(program, i.id, r, sizeof name, nullptr, name);
      if (std::string(name).rfind(skip_prefix, 0) == 0) continue;
      std::vector<GLint> values(i.properties.size());
      glGetProgramResourceiv(program, i.id, r, static_cast<GLsizei>(i.properties.size()), i.properties.data(),
                             static_cast<GLsizei>(values.size()), nullptr, values.data());
      std::ostringstream line;
      line << i.name << ' ' << name;
      for (GLint v : values) line << ' ' << v;
      lines.push_back(line.str());
    }
  }
  std::sort(lines.begin(), lines.end());
  std::string table;
  for (const std::string& l : lines) table += l + "\n";
  return table;
}

std::vector<int> logged_lines(const std::string& log) {
  static const std::regex position(R"((?:^|\n)\d+:(\d+)\()");
  std::vector<int> lines;
  for (auto it = std::sregex_iterator(log.begin(), log.end(), position); it != std::sregex_iterator(); ++it)
    lines.push_back(std::stoi((*it)[1]));
  return lines;
}

QuadTarget::QuadTarget(int size) : size_(size) {
  glGenTextures(1, &colour_);
  glBindTexture(GL_TEXTURE_2D, colour_);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, size_, size_, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  glGenFramebuffers(1, &framebuffer_);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colour_, 0);

  std::vector<std::uint8_t> gradient(kSize * kSize * 4);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      std::uint8_t* p = &gradient[(y * kSize + x) * 4];
      p[0] = static_cast<std::uint8_t>(x * 4);
      p[1] = static_cast<std::uint8_t>(y * 4);
      p[2] = static_cast<std::uint8_t>((x ^ y) * 4);
      p[3] = 255;
    }
  glActiveTexture(GL_TEXTURE0);
  glGenTextures(1, &texture_);
  glBindTexture(GL_TEXTURE_2D, texture_);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, kSize, kSize, 0, GL_RGBA, GL_UNSIGNED_BYTE, gradient.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);

  const float quad[] = {-1, -1, 1, -1, 1, 1, -1, -1, 1, 1, -1, 1};
  glGenVertexArrays(1, &vertex_array_);
  glBindVertexArray(vertex_array_);
  glGenBuffers(1, &vertices_);
  glBindBuffer(GL_ARRAY_BUFFER, vertices_);
  glBufferData(GL_ARRAY_BUFFER, sizeof quad, quad, GL_STATIC_DRAW);
  glViewport(0, 0, size_, size_);
}

QuadTarget::~QuadTarget() {
  glDeleteBuffers(1, &vertices_);
  glDeleteVertexArrays(1, &vertex_array_);
  glDeleteTextures(1, &texture_);
  glDeleteFramebuffers(1, &framebuffer_);
  glDeleteTextures(1, &colour_);
}

void QuadTarget::draw_without_readback(GLuint program) {
  glUseProgram(program);
  const GLint position = glGetAttribLocation(program, "position");
  glBindVertexArray(vertex_array_);
  glBindBuffer(GL_ARRAY_BUFFER, vertices_);
  glVertexAttribPointer(static_cast<GLuint>(position), 2, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(static_cast<GLuint>(position));
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glClearColor(0.25f, 0.5f, 0.75f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  glDrawArrays(GL_TRIANGLES, 0, 6);
}

std::vector<std::uint8_t> QuadTarget::draw(GLuint program) {
  draw_without_readback(program);
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(size_) * size_ * 4);
  glReadPixels(0, 0, size_, size_, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
  return pixels;
}

}  // namespace glbudget::test
