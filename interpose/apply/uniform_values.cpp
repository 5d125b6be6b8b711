#include "uniform_values.hpp"

#include <algorithm>

#include "apply_gl.hpp"

namespace glbudget {

namespace {

enum class Base { f, i, u, d };

struct TypeInfo {
  Base base = Base::i;
  int components = 1;  // per element
  int columns = 0;     // matrices only
  int rows = 0;
};

bool describe(GLenum type, TypeInfo* t) {
  switch (type) {
    case GL_FLOAT:
      *t = {Base::f, 1};
      return true;
    case GL_FLOAT_VEC2:
      *t = {Base::f, 2};
      return true;
    case GL_FLOAT_VEC3:
      *t = {Base::f, 3};
      return true;
    case GL_FLOAT_VEC4:
      *t = {Base::f, 4};
      return true;
    case GL_DOUBLE:
      *t = {Base::d, 1};
      return true;
    case GL_DOUBLE_VEC2:
      *t = {Base::d, 2};
      return true;
    case GL_DOUBLE_VEC3:
      *t = {Base::d, 3};
      return true;
    case GL_DOUBLE_VEC4:
      *t = {Base::d, 4};
      return true;
    case GL_INT:
    case GL_BOOL:
      *t = {Base::i, 1};
      return true;
    case GL_INT_VEC2:
    case GL_BOOL_VEC2:
      *t = {Base::i, 2};
      return true;
    case GL_INT_VEC3:
    case GL_BOOL_VEC3:
      *t = {Base::i, 3};
      return true;
    case GL_INT_VEC4:
    case GL_BOOL_VEC4:
      *t = {Base::i, 4};
      return true;
    case GL_UNSIGNED_INT:
      *t = {Base::u, 1};
      return true;
    case GL_UNSIGNED_INT_VEC2:
      *t = {Base::u, 2};
      return true;
    case GL_UNSIGNED_INT_VEC3:
      *t = {Base::u, 3};
      return true;
    case GL_UNSIGNED_INT_VEC4:
      *t = {Base::u, 4};
      return true;
    case GL_FLOAT_MAT2:
      *t = {Base::f, 4, 2, 2};
      return true;
    case GL_FLOAT_MAT3:
      *t = {Base::f, 9, 3, 3};
      return true;
    case GL_FLOAT_MAT4:
      *t = {Base::f, 16, 4, 4};
      return true;
    case GL_FLOAT_MAT2x3:
      *t = {Base::f, 6, 2, 3};
      return true;
    case GL_FLOAT_MAT2x4:
      *t = {Base::f, 8, 2, 4};
      return true;
    case GL_FLOAT_MAT3x2:
      *t = {Base::f, 6, 3, 2};
      return true;
    case GL_FLOAT_MAT3x4:
      *t = {Base::f, 12, 3, 4};
      return true;
    case GL_FLOAT_MAT4x2:
      *t = {Base::f, 8, 4, 2};
      return true;
    case GL_FLOAT_MAT4x3:
      *t = {Base::f, 12, 4, 3};
      return true;
    case GL_DOUBLE_MAT2:
      *t = {Base::d, 4, 2, 2};
      return true;
    case GL_DOUBLE_MAT3:
      *t = {Base::d, 9, 3, 3};
      return true;
    case GL_DOUBLE_MAT4:
      *t = {Base::d, 16, 4, 4};
      return true;
    case GL_DOUBLE_MAT2x3:
      *t = {Base::d, 6, 2, 3};
      return true;
    case GL_DOUBLE_MAT2x4:
      *t = {Base::d, 8, 2, 4};
      return true;
    case GL_DOUBLE_MAT3x2:
      *t = {Base::d, 6, 3, 2};
      return true;
    case GL_DOUBLE_MAT3x4:
      *t = {Base::d, 12, 3, 4};
      return true;
    case GL_DOUBLE_MAT4x2:
      *t = {Base::d, 8, 4, 2};
      return true;
    case GL_DOUBLE_MAT4x3:
      *t = {Base::d, 12, 4, 3};
      return true;
    case GL_UNSIGNED_INT_ATOMIC_COUNTER:
      return false;  // bound by offset, never set
    default:
      *t = {Base::i, 1};
      return true;  // samplers and images: a unit number
  }
}

template <typename T>
bool write(GLuint program, GLint location, const TypeInfo& t, GLsizei count, const T* v);

template <>
bool write<GLfloat>(GLuint p, GLint l, const TypeInfo& t, GLsizei n, const GLfloat* v) {
  const ApplyGl& g = agl();
  if (t.columns == 0) {
    switch (t.components) {
      case 1:
        return g.ProgramUniform1fv && (g.ProgramUniform1fv(p, l, n, v), true);
      case 2:
        return g.ProgramUniform2fv && (g.ProgramUniform2fv(p, l, n, v), true);
      case 3:
        return g.ProgramUniform3fv && (g.ProgramUniform3fv(p, l, n, v), true);
      default:
        return g.ProgramUniform4fv && (g.ProgramUniform4fv(p, l, n, v), true);
    }
  }
  PFNGLPROGRAMUNIFORMMATRIX4FVPROC fn = nullptr;
  switch (t.columns * 10 + t.rows) {
    case 22:
      fn = g.ProgramUniformMatrix2fv;
      break;
    case 33:
      fn = g.ProgramUniformMatrix3fv;
      break;
    case 44:
      fn = g.ProgramUniformMatrix4fv;
      break;
    case 23:
      fn = g.ProgramUniformMatrix2x3fv;
      break;
    case 24:
      fn = g.ProgramUniformMatrix2x4fv;
      break;
    case 32:
      fn = g.ProgramUniformMatrix3x2fv;
      break;
    case 34:
      fn = g.ProgramUniformMatrix3x4fv;
      break;
    case 42:
      fn = g.ProgramUniformMatrix4x2fv;
      break;
    case 43:
      fn = g.ProgramUniformMatrix4x3fv;
      break;
  }
  return fn && (fn(p, l, n, GL_FALSE, v), true);
}

template <>
bool write<GLdouble>(GLuint p, GLint l, const TypeInfo& t, GLsizei n, const GLdouble* v) {
  const ApplyGl& g = agl();
  if (t.columns == 0) {
    switch (t.components) {
      case 1:
        return g.ProgramUniform1dv && (g.ProgramUniform1dv(p, l, n, v), true);
      case 2:
        return g.ProgramUniform2dv && (g.ProgramUniform2dv(p, l, n, v), true);
      case 3:
        return g.ProgramUniform3dv && (g.ProgramUniform3dv(p, l, n, v), true);
      default:
        return g.ProgramUniform4dv && (g.ProgramUniform4dv(p, l, n, v), true);
    }
  }
  PFNGLPROGRAMUNIFORMMATRIX4DVPROC fn = nullptr;
  switch (t.columns * 10 + t.rows) {
    case 22:
      fn = g.ProgramUniformMatrix2dv;
      break;
    case 33:
      fn = g.ProgramUniformMatrix3dv;
      break;
    case 44:
      fn = g.ProgramUniformMatrix4dv;
      break;
    case 23:
      fn = g.ProgramUniformMatrix2x3dv;
      break;
    case 24:
      fn = g.ProgramUniformMatrix2x4dv;
      break;
    case 32:
      fn = g.ProgramUniformMatrix3x2dv;
      break;
    case 34:
      fn = g.ProgramUniformMatrix3x4dv;
      break;
    case 42:
      fn = g.ProgramUniformMatrix4x2dv;
      break;
    case 43:
      fn = g.ProgramUniformMatrix4x3dv;
      break;
  }
  return fn && (fn(p, l, n, GL_FALSE, v), true);
}

template <>
bool write<GLint>(GLuint p, GLint l, const TypeInfo& t, GLsizei n, const GLint* v) {
  const ApplyGl& g = agl();
  switch (t.components) {
    case 1:
      return g.ProgramUniform1iv && (g.ProgramUniform1iv(p, l, n, v), true);
    case 2:
      return g.ProgramUniform2iv && (g.ProgramUniform2iv(p, l, n, v), true);
    case 3:
      return g.ProgramUniform3iv && (g.ProgramUniform3iv(p, l, n, v), true);
    default:
      return g.ProgramUniform4iv && (g.ProgramUniform4iv(p, l, n, v), true);
  }
}

template <>
bool write<GLuint>(GLuint p, GLint l, const TypeInfo& t, GLsizei n, const GLuint* v) {
  const ApplyGl& g = agl();
  switch (t.components) {
    case 1:
      return g.ProgramUniform1uiv && (g.ProgramUniform1uiv(p, l, n, v), true);
    case 2:
      return g.ProgramUniform2uiv && (g.ProgramUniform2uiv(p, l, n, v), true);
    case 3:
      return g.ProgramUniform3uiv && (g.ProgramUniform3uiv(p, l, n, v), true);
    default:
      return g.ProgramUniform4uiv && (g.ProgramUniform4uiv(p, l, n, v), true);
  }
}

template <typename T>
bool write_converted(GLuint p, GLint l, const TypeInfo& t, GLsizei n, const std::vector<double>& values) {
  std::vector<T> v(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(n) * t.components);
  return write<T>(p, l, t, n, v.data());
}

}  // namespace

int uniform_components(GLenum type) {
  TypeInfo t;
  return describe(type, &t) ? t.components : 0;
}

bool copy_uniform(GLuint from, GLint from_location, GLuint to, GLint to_location, GLenum type) {
  TypeInfo t;
  if (!describe(type, &t)) return false;
  const ApplyGl& g = agl();
  switch (t.base) {
    case Base::f: {
      GLfloat v[16];
      if (!g.GetUniformfv) return false;
      g.GetUniformfv(from, from_location, v);
      return write<GLfloat>(to, to_location, t, 1, v);
    }
    case Base::d: {
      GLdouble v[16];
      if (!g.GetUniformdv) return false;
      g.GetUniformdv(from, from_location, v);
      return write<GLdouble>(to, to_location, t, 1, v);
    }
    case Base::i: {
      GLint v[4];
      if (!g.GetUniformiv) return false;
      g.GetUniformiv(from, from_location, v);
      return write<GLint>(to, to_location, t, 1, v);
    }
    case Base::u: {
      GLuint v[4];
      if (!g.GetUniformuiv) return false;
      g.GetUniformuiv(from, from_location, v);
      return write<GLuint>(to, to_location, t, 1, v);
    }
  }
  return false;
}

bool set_uniform(GLuint program, GLint location, GLenum type, GLint max_elements, const std::vector<double>& values) {
  TypeInfo t;
  if (!describe(type, &t) || values.empty() || values.size() % static_cast<size_t>(t.components) != 0) return false;
  const auto n = static_cast<GLsizei>(std::min<size_t>(values.size() / static_cast<size_t>(t.components),
                                                       static_cast<size_t>(max_elements < 1 ? 1 : max_elements)));
  switch (t.base) {
    case Base::f:
      return write_converted<GLfloat>(program, location, t, n, values);
    case Base::d:
      return write_converted<GLdouble>(program, location, t, n, values);
    case Base::i:
      return write_converted<GLint>(program, location, t, n, values);
    case Base::u:
      return write_converted<GLuint>(program, location, t, n, values);
  }
  return false;
}

}  // namespace glbudget
